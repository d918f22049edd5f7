"""What the plotting tools do with an input that is not what they draw: one line naming the file and what
went wrong, exit status 2, instead of a Python traceback (a run's HDF5 given to the splash plot, a folder
given for a file, a file cut short).

Each tool ends with `tool_errors.run(main, "a `grainlab run` file")`.
"""
import sys


def run(main, reads):
    """Runs main(); an input it cannot read ends the tool with `error: INPUT: ...` and status 2."""
    try:
        main()
    except (KeyError, OSError, ValueError, IndexError, TypeError) as e:
        where = sys.argv[1] if len(sys.argv) > 1 else "input"
        why = " ".join(str(e).split())  # (h5py's messages run over several lines)
        print(f"error: {where}: cannot be drawn as {reads}: {type(e).__name__}: {why}", file=sys.stderr)
        sys.exit(2)
