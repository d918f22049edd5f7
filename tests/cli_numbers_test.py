"""No command takes NaN, an infinity or a number outside an option's stated range: each is refused at once,
with the option's name (and, for a range, its bounds as the help gives them).

Usage: cli_numbers_test.py GRAINLAB SOURCE_DIR. Walks every subcommand listed by `--help` (and theirs), and for each
numeric option (CLI11 type FLOAT) passes nan, inf and -inf in turn. Each call must exit with status 2 and
name the option on stderr, within 20 s: CLI11's range checks compare, every comparison with NaN is false,
and before grainlab checked for it `ripples hybrid-flux --ustar nan` reached the model and `sand-gun
--stiffness nan` poured a bed before failing on a derived time step. Then for each option whose help states
a range ("FLOAT in [lo, hi]", "(lo, hi)" and the like, POSITIVE, NONNEGATIVE) a value just outside it: CLI11's own checks printed
their bounds with std::to_string ("Value 0 not in range 0.000000 to 1000000.000000", a positive number's
upper bound in 300 digits).
"""
import re
import subprocess
import sys

grainlab, source = sys.argv[1], sys.argv[2]
# What each command requires before any option of its own is looked at (files need only exist: the numbers
# are checked before anything is read). Output paths are never written: every call is refused first.
scene = f"{source}/scenes/two_disc_collision.toml"
required = {
    "run": [scene], "inspect": [scene], "bed": ["--out", "/tmp/never-written.h5"], "impact": ["--case", "A"],
    "splash": ["--out", "/tmp/never-written.h5"], "saltation conveyor": ["--case", "D"],
    "saltation study": ["--out", "/tmp/never-written"],
    "ripples lattice": ["--config", f"{source}/scenes/ripples/lattice_fig5_22.toml"],
    "ripples analyze": [scene], "ripples hybrid": ["--config", f"{source}/scenes/ripples/hybrid_quick.toml"],
}


def help_of(path):
    return subprocess.run([grainlab] + path + ["--help"], capture_output=True, text=True, timeout=20).stdout


def commands(path):
    """Every subcommand path below `path`, depth first, with its help text."""
    text = help_of(path)
    yield path, text
    if "Subcommands:" in text:
        for line in text.split("Subcommands:", 1)[1].splitlines():
            m = re.match(r"^  (\S+)\s", line)
            if m:
                yield from commands(path + [m.group(1)])


tried = 0
for path, text in commands([]):
    assert "REQUIRED" not in text or " ".join(path) in required, f"{' '.join(path)}: requires what this test does not give"
    options = text.split("Subcommands:", 1)[0]
    for m in re.finditer(r"^\s+(?:-\w,)?(--[\w-]+)\s+FLOAT", options, re.M):
        option = m.group(1)
        for value in ("nan", "inf", "-inf"):
            # (the option's value after '=' so that a negative number is not read as an option)
            run = subprocess.run([grainlab] + path + required.get(" ".join(path), []) + [f"{option}={value}"],
                                 capture_output=True, text=True, timeout=20)
            where = " ".join(path + [f"{option}={value}"])
            assert run.returncode == 2, f"{where}: exit status {run.returncode}\n{run.stderr}"
            assert option in run.stderr, f"{where}: the message does not name {option}:\n{run.stderr}"
            tried += 1
assert tried > 100, f"only {tried} numeric options found: has the help's format changed?"
print(f"{tried} non-finite values refused by name")


def outside(kind, left, lo, hi, right):
    """Values just outside a range for an option read as `kind`, with the message each must give: below
    and above it, and an open end itself."""
    message = f"must lie in {left}{lo}, {hi}{right}"
    yield (str(int(lo) - 1) if kind != "FLOAT" else repr(float(lo) - 1)), message
    yield (str(int(hi) + 1) if kind != "FLOAT" else repr(float(hi) * 2 + 1)), message
    if left == "(":
        yield lo, message
    if right == ")":
        yield hi, message


ranged = 0
for path, text in commands([]):
    options = text.split("Subcommands:", 1)[0]
    pattern = (r"^\s+(?:-\w,)?(--[\w-]+)\s+(FLOAT|INT|UINT):(?:(?:FLOAT|INT|UINT) in ([[(])([^],)\s]+), "
               r"([^])\s]+)([])])|(POSITIVE|NONNEGATIVE))")
    for m in re.finditer(pattern, options, re.M):
        option, kind, left, lo, hi, right, sign = m.groups()
        cases = list(outside(kind, left, lo, hi, right)) if lo else [("0", "must be > 0")] if sign == "POSITIVE" else [("-1", "must be >= 0")]
        for value, message in cases:
            run = subprocess.run([grainlab] + path + required.get(" ".join(path), []) + [f"{option}={value}"],
                                 capture_output=True, text=True, timeout=20)
            where = " ".join(path + [f"{option}={value}"])
            assert run.returncode == 2, f"{where}: exit status {run.returncode}\n{run.stderr}"
            assert f"{option}: {value}: {message}" in run.stderr, f"{where}: not '{message}', naming the option:\n{run.stderr}"
            ranged += 1
assert ranged > 100, f"only {ranged} values outside ranges tried: has the help's format changed?"
print(f"{ranged} values outside an option's range refused by name, with its bounds")
