"""A run stopped by a signal leaves no temporary file and keeps its last whole checkpoint.

Usage: interrupted_run_test.py GRAINLAB CONFIG SIGNAL (INT, TERM or HUP). Starts a long hybrid ripple run
with an output file and checkpoints, waits until both exist, stops it with the signal, and checks that the
process ended by that signal, that no *.tmp-* file is left, that no output file was committed, and that
the checkpoint is a whole HDF5 file a run can continue from.
"""
import glob
import os
import signal
import subprocess
import sys
import tempfile

import h5py
from stopping import stop_when

grainlab, config, name = sys.argv[1], sys.argv[2], sys.argv[3]
sig = getattr(signal, "SIG" + name)
with tempfile.TemporaryDirectory() as d:
    out, ck = os.path.join(d, "run.h5"), os.path.join(d, "run.ck")
    run = subprocess.Popen([grainlab, "ripples", "hybrid", "--config", config, "--duration", "1e6",
                            "--out", out, "--checkpoint", ck, "--checkpoint-every", "20", "--quiet"],
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    # (settle: into the run's work, possibly into a checkpoint being written)
    stop_when(run, lambda: os.path.exists(ck) and glob.glob(out + ".tmp-*"), "checkpoint and temporary output", 60,
              sig, settle=0.3)
    left = sorted(os.listdir(d))
    assert not [f for f in left if ".tmp-" in f], f"temporary files left: {left}"
    assert left == ["run.ck"], f"expected only the checkpoint, found {left}"
    with h5py.File(ck, "r") as f:
        assert "cli/history" in f and "run/bed" in f, f"the checkpoint lacks its parts: {list(f)}"
print(f"SIG{name}: stopped, no temporary file left, checkpoint whole")
