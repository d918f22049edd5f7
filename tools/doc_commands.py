#!/usr/bin/env python3
"""Check that the grainlab commands the docs show still match the command line.

Every `grainlab ...` command in the given markdown files (fenced code blocks, and inline code spans that
start with `grainlab`, `build/release/grainlab` or one of its subcommands and pass an --option) is read as a user would type it: its subcommands must
exist, each --option it passes must be one that subcommand (or a parent) lists in its --help, and each
scene or config under scenes/ it names must be in the repository. Placeholders in capitals (MODEL, FILE)
and optional parts in brackets are allowed. Prints one line per problem, `FILE:LINE: ...`, and exits 1 if
there is any (0 otherwise, 2 for bad arguments).

    tools/doc_commands.py --grainlab build/release/grainlab README.md docs/*.md
"""
import argparse
import os
import re
import shlex
import subprocess
import sys

FENCE = re.compile(r"^```")
SHORT = re.compile(r"[a-z][a-z0-9-]* .*--[a-z].*")
SHELL_BREAKS = re.compile(r"\s(?:&&|\|\||\||;|>>|>|2>|<)\s|\s&$")


class Cli:
    """grainlab's subcommands and options, read from its --help (cached per subcommand path)."""

    def __init__(self, binary):
        self.binary = binary
        self.cache = {}

    def help(self, path):
        key = tuple(path)
        if key not in self.cache:
            out = subprocess.run([self.binary, *path, "--help"], capture_output=True, text=True, timeout=60)
            text = out.stdout
            subs = set()
            section = None
            options = set()
            for line in text.splitlines():
                if line.startswith("Subcommands:"):
                    section = "subs"
                    continue
                if line.startswith("Options:"):
                    section = "options"
                    continue
                if section == "subs":
                    m = re.match(r"^  (\S+)\s", line)
                    if m:
                        subs.add(m.group(1))
                if section == "options":
                    m = re.match(r"^  (\S+)", line)
                    if m:
                        for name in m.group(1).split(","):
                            options.add(name.split(" ")[0])
            self.cache[key] = (subs, options)
        return self.cache[key]


def commands(path, top_level):
    """(line number, command text) for each grainlab command in a markdown file; `top_level`: grainlab's
    subcommands, which an inline span may start with instead of its name."""
    lines = open(path, encoding="utf-8").read().split("\n")
    in_code = False
    pending, start = "", 0
    prose = []  # (line number, text) of the lines outside code blocks: inline spans may wrap
    for n, line in enumerate(lines, 1):
        if FENCE.match(line.strip()):
            in_code = not in_code
            pending = ""
            continue
        if not in_code:
            prose.append((n, line))
            continue
        if pending:
            pending += " " + line.strip()
        else:
            pending, start = line.strip(), n
        if pending.endswith("\\"):
            pending = pending[:-1]
            continue
        text, pending = pending, ""
        if re.search(r"(^|[\s/])grainlab\s", text) and not text.startswith("#"):
            yield start, text
    yield from inline_commands(prose, top_level)


def inline_commands(prose, top_level):
    """The commands in inline code spans, which may run over a line break within a paragraph."""
    text = "\n".join(line for _, line in prose)
    first_line = [n for n, _ in prose]
    line_of = lambda offset: first_line[text.count("\n", 0, offset)]
    for m in re.finditer(r"`([^`]+)`", text):
        span = " ".join(m.group(1).split())
        if re.match(r"(?:build/release/)?grainlab ", span):
            yield line_of(m.start()), span
        elif SHORT.fullmatch(span) and span.split()[0] in top_level:  # `saltation wind --json`
            yield line_of(m.start()), "grainlab " + span


def grainlab_part(text):
    """The tokens after `grainlab` in the shell segment that runs it (comments and pipes cut off)."""
    text = re.sub(r"\s#\s.*$|\s#$", "", text)
    for segment in SHELL_BREAKS.split(" " + text + " "):
        m = re.search(r"(?:^|[\s/])grainlab(?:\.\S+)?\s(.*)$", segment)
        if m:
            try:
                return shlex.split(m.group(1))
            except ValueError:
                return shlex.split(m.group(1).replace("'", "").replace('"', ""))
    return None


def placeholder(token):
    return bool(re.fullmatch(r"[A-Z][A-Z0-9_]*|\S*\.\.\.", token))


def check(cli, tokens, repo):
    """Problems with one command's tokens."""
    problems = []
    path = []
    subs, _ = cli.help(path)
    i = 0
    while i < len(tokens):
        t = tokens[i].strip("[]()")
        if t in subs:
            path.append(t)
            subs, _ = cli.help(path)
            i += 1
            continue
        break
    if not path:
        if tokens and not tokens[0].startswith("-") and not placeholder(tokens[0].strip("[]")):
            problems.append(f"no subcommand '{tokens[0]}'")
        return problems
    known = set()
    for k in range(len(path) + 1):
        known |= cli.help(path[:k])[1]
    if subs and i < len(tokens):  # a group whose subcommand is not named: a placeholder or a mistake
        t = tokens[i].strip("[]")
        if not t.startswith("-") and not placeholder(t):
            problems.append(f"no subcommand '{t}' under '{' '.join(path)}'")
    for t in tokens[i:]:
        t = t.strip("[](){}|,")
        if re.fullmatch(r"--[a-z][a-z0-9-]*(=.*)?", t):
            name = t.split("=")[0]
            if name not in known:
                problems.append(f"'{' '.join(path)}' has no option {name}")
        elif re.fullmatch(r"scenes/\S+\.toml", t) and not os.path.exists(os.path.join(repo, t)):
            problems.append(f"no file {t}")
    return problems


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--grainlab", required=True, help="the grainlab binary to ask for --help")
    ap.add_argument("--repo", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."),
                    help="where scenes/ is (default: this tool's repository)")
    ap.add_argument("files", nargs="+")
    a = ap.parse_args()
    if not os.access(a.grainlab, os.X_OK):
        print(f"doc_commands: {a.grainlab}: not an executable", file=sys.stderr)
        return 2
    cli = Cli(a.grainlab)
    top_level = cli.help([])[0]
    bad = seen = 0
    for f in a.files:
        for n, text in commands(f, top_level):
            tokens = grainlab_part(text)
            if tokens is None:
                continue
            seen += 1
            for p in check(cli, tokens, a.repo):
                print(f"{f}:{n}: {p}: {text}")
                bad += 1
    print(f"doc_commands: {seen} commands read, {bad} problems", file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
