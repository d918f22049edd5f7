"""Stopping a grainlab process by a signal at a chosen point, for the tests of what a stop leaves."""
import time


def stop_when(run, ready, what, seconds, sig, settle=0.0):
    """Waits (at most `seconds`) until ready() holds while `run` (a Popen) is still going, then sends `sig`
    and checks that the process ended by it. `what` names the awaited point in failure messages; `settle`
    waits a little longer first, to stop it inside its work rather than at that point."""
    deadline = time.time() + seconds
    while not ready():
        assert run.poll() is None, f"it ended before it was stopped: {run.stderr.read()}"
        assert time.time() < deadline, f"no {what} within {seconds} s"
        time.sleep(0.02)
    time.sleep(settle)
    run.send_signal(sig)
    run.wait(timeout=60)
    assert run.returncode == -sig, f"ended with {run.returncode}, not by signal {int(sig)}"
