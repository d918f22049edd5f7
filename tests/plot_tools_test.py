"""Every plotting tool given an input it does not draw ends with one line naming the input and exit status
2, not a Python traceback: a text file, a folder, and a file of another kind (the shipped splash file, which
every tool but plot_splash.py reads as foreign).

Usage: plot_tools_test.py SOURCE_DIR SCRATCH_DIR
"""
import os
import subprocess
import sys

source, scratch = sys.argv[1], sys.argv[2]
os.makedirs(scratch, exist_ok=True)
text = os.path.join(scratch, "not-hdf5.h5")
with open(text, "w") as f:
    f.write("not an HDF5 file\n")
splash = os.path.join(source, "data", "splash", "discs2d.h5")
tools = ["plot_frame", "plot_hybrid", "plot_ripples", "plot_splash", "plot_saltation", "plot_continuum",
         "plot_report", "plot_saltation_study"]
tried = 0
for tool in tools:
    for given in (text, scratch, splash):
        if tool == "plot_splash" and given == splash:
            continue
        out = [] if tool == "plot_report" else [os.path.join(scratch, "never.png")]  # (it draws into the folder)
        run = subprocess.run(["/usr/bin/python3", os.path.join(source, "tools", tool + ".py"), given] + out,
                             capture_output=True, text=True, timeout=60)
        where = f"{tool} {given}"
        assert run.returncode == 2, f"{where}: exit status {run.returncode}\n{run.stderr}"
        assert "Traceback" not in run.stderr, f"{where}: a traceback:\n{run.stderr}"
        lines = run.stderr.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith(f"error: {given}: "), f"{where}: not one line naming it:\n{run.stderr}"
        assert not os.path.exists(os.path.join(scratch, "never.png")), f"{where}: wrote a figure"
        tried += 1
print(f"{tried} foreign inputs refused in one line")
