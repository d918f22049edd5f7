#!/usr/bin/env python3
"""Keeps the contents lists of the long pages in docs/ up to date.

A page opts in with a block

    <!-- contents -->
    <!-- /contents -->

which this tool fills with a link to every `##` and `###` heading below it (GitHub's anchors).

    /usr/bin/python3 tools/doc_contents.py docs/*.md            # rewrite the blocks
    /usr/bin/python3 tools/doc_contents.py --check docs/*.md    # exit 1 naming each stale page (a ctest)

Pages without a block are left alone.
"""
import argparse
import functools
import os
import re
import sys

OPEN, CLOSE = "<!-- contents -->", "<!-- /contents -->"


def link_text(title):
    """A heading with its links replaced by their text."""
    return re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", title)


def anchor(title, seen):
    """GitHub's anchor for a heading: markup dropped, lower case, punctuation out, spaces to hyphens;
    a repeated heading gets -1, -2, ..."""
    text = link_text(title).replace("`", "").replace("*", "").strip().lower()
    text = re.sub(r"[^\w\- ]", "", text).replace(" ", "-")
    n = seen.get(text, 0)
    seen[text] = n + 1
    return text if n == 0 else f"{text}-{n}"


def headings(lines):
    """(level, title) of every ## and ### heading outside code fences."""
    fenced = False
    for line in lines:
        if line.startswith("```"):
            fenced = not fenced
            continue
        m = None if fenced else re.match(r"^(#{1,6}) (.+?)\s*$", line)
        if m:
            yield len(m.group(1)), m.group(2)


def contents(lines):
    """The block's lines for a page (every heading counts toward repeated anchors, as on GitHub)."""
    seen, out = {}, []
    for level, title in headings(lines):
        a = anchor(title, seen)
        if level in (2, 3):
            out.append(f"{'  ' * (level - 2)}- [{link_text(title)}](#{a})")
    return out


def refreshed(text):
    """The page with its block filled, or None when it has no block."""
    lines = text.split("\n")
    if OPEN not in lines:
        return None
    start = lines.index(OPEN)
    if CLOSE not in lines[start:]:
        raise ValueError(f"'{OPEN}' without '{CLOSE}'")
    end = start + lines[start:].index(CLOSE)
    body = lines[:start] + lines[end + 1:]
    return "\n".join(lines[: start + 1] + contents(body) + lines[end:])


@functools.lru_cache(maxsize=None)
def anchors_of(page):
    """Every heading anchor of a page (read once, however many links point into it)."""
    with open(page, encoding="utf-8") as f:
        seen = {}
        return frozenset(anchor(t, seen) for _, t in headings(f.read().split("\n")))


def broken_links(path, text):
    """Links of a page to files that do not exist, or to anchors its target page lacks (http links and
    images are not followed)."""
    here = os.path.dirname(path)
    out = []
    for m in re.finditer(r"(?<!!)\[[^\]\n]*\]\(([^)\s]+)\)", text):
        target = m.group(1)
        if re.match(r"[a-z]+:", target):
            continue
        file, _, frag = target.partition("#")
        dest = os.path.normpath(os.path.join(here, file)) if file else path
        if not os.path.exists(dest):
            out.append(f"{path}: link to {target}: no such file")
        elif frag and dest.endswith(".md") and frag not in anchors_of(dest):
            out.append(f"{path}: link to {target}: no such heading")
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--check", action="store_true", help="change nothing; exit 1 if a block is stale")
    p.add_argument("--links", action="store_true", help="also exit 1 on a link to a missing file or heading")
    p.add_argument("pages", nargs="+")
    a = p.parse_args()
    failed = False
    for path in a.pages:
        with open(path, encoding="utf-8") as f:
            text = f.read()
        if a.links:
            for line in broken_links(path, text):
                print(line, file=sys.stderr)
                failed = True
        try:
            new = refreshed(text)
        except ValueError as e:
            print(f"{path}: {e}", file=sys.stderr)
            return 2
        if new is None or new == text:
            continue
        if a.check:
            print(f"{path}: contents are stale; run /usr/bin/python3 tools/doc_contents.py {path}", file=sys.stderr)
            failed = True
        else:
            with open(path + ".tmp", "w", encoding="utf-8") as f:
                f.write(new)
            os.replace(path + ".tmp", path)
            print(f"{path}: contents rewritten")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
