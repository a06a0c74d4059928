#!/usr/bin/env python3
"""Checks that every relative link in the project's Markdown resolves: README.md, docs/*.md,
core/'s READMEs and the benches' results (bench/results/*.md) by default, or the files given. A
link resolves when the file or folder it names exists (relative to the file that holds it) and,
when it has a #fragment into a Markdown file, that
file has a heading with that anchor (GitHub's: lower case, punctuation dropped, spaces to
hyphens, -1, -2, ... for repeats). Links with a scheme (https:, mailto:) are not checked, nor
anything inside code (fenced blocks and `spans`).

  python3 scripts/check-links.py                 README.md, docs/*.md, core/**/README.md and
                                                 bench/results/*.md here
  python3 scripts/check-links.py FILE.md ...     those files
  python3 scripts/check-links.py --inside DIR FILE.md ...
                                                 also fails a link that leaves DIR (an installed
                                                 doc folder must hold everything its README links)
  python3 scripts/check-links.py --closure FILE.md ...
                                                 prints, one per line relative to the repository,
                                                 every local file those files link to, following
                                                 links in linked Markdown too (what a package
                                                 ships beside its docs so that they resolve)

Exit 1 naming every broken link, else prints how many links were checked. Python 3 standard
library only (tests/packages/deb_test.py imports it for the installed README)."""
import argparse
import os
import pathlib
import re
import sys
import unicodedata

REPO = pathlib.Path(__file__).resolve().parent.parent

# [text](target "title") and ![alt](target): the text may hold one level of brackets, the target
# one level of parentheses.
INLINE = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]"
                    r"\(\s*<?([^()\s>]+(?:\([^()\s]*\))?)>?(?:\s+\"[^\"]*\")?\s*\)")
REFERENCE = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+.*)?$")
HTML = re.compile(r"<(?:img|a|source)\b[^>]*?\b(?:src|href)\s*=\s*\"([^\"]+)\"", re.I)
CODE_SPAN = re.compile(r"(`+).*?\1")
SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")


def lines_outside_fences(text):
    """(line number, line) of every line of Markdown TEXT outside fenced code blocks."""
    fence = None
    for number, line in enumerate(text.splitlines(), 1):
        stripped = line.lstrip()
        if fence:
            if stripped.startswith(fence):
                fence = None
            continue
        if stripped.startswith("```") or stripped.startswith("~~~"):
            fence = stripped[:3]
            continue
        yield number, line


def links(text):
    """(line number, target) of every link outside code in Markdown TEXT."""
    found = []
    for number, line in lines_outside_fences(text):
        line = CODE_SPAN.sub("", line)
        for pattern in (INLINE, HTML):
            found += [(number, m.group(1)) for m in pattern.finditer(line)]
        m = REFERENCE.match(line)
        if m:
            found.append((number, m.group(1)))
    return found


def relative_links(text):
    """links(TEXT) without the ones that have a scheme (https:, mailto:, ...)."""
    return [(n, t) for n, t in links(text) if not SCHEME.match(t)]


def slug(heading):
    """GitHub's anchor of a heading's text."""
    text = re.sub(r"<[^>]+>", "", heading)            # inline HTML
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", text)  # links keep their text
    text = text.replace("`", "").strip().lower()
    kept = []
    for ch in text:
        if ch in " -_" or unicodedata.category(ch)[0] in "LNM":
            kept.append(ch)
    return "".join(kept).replace(" ", "-")


def anchors(path, cache={}):
    """Every heading anchor of the Markdown file PATH."""
    if path not in cache:
        seen = {}
        result = set()
        for _, line in lines_outside_fences(path.read_text(encoding="utf-8")):
            m = re.match(r"^ {0,3}(#{1,6})\s+(.*?)\s*#*\s*$", line)
            if not m:
                continue
            base = slug(m.group(2))
            count = seen.get(base, 0)
            seen[base] = count + 1
            result.add(base if count == 0 else f"{base}-{count}")
        for m in re.finditer(r"<a\s+(?:name|id)=\"([^\"]+)\"", path.read_text(encoding="utf-8")):
            result.add(m.group(1))
        cache[path] = result
    return cache[path]


def resolve(path, target):
    """(the file or folder a relative link TARGET in the Markdown file PATH names, its #fragment):
    a link with only a fragment names PATH itself."""
    name, _, fragment = target.partition("#")
    name = re.sub(r"%20", " ", name)
    return ((path.parent / name).resolve() if name else path.resolve()), fragment


def broken(path, inside=None):
    """(line, target, reason) of every relative link in the Markdown file PATH that does not
    resolve (or, with INSIDE, leaves that folder)."""
    path = pathlib.Path(path)
    problems = []
    for number, target in relative_links(path.read_text(encoding="utf-8")):
        resolved, fragment = resolve(path, target)
        if inside is not None:
            root = pathlib.Path(inside).resolve()
            if os.path.commonpath([root, resolved]) != str(root):
                problems.append((number, target, f"leaves {inside}"))
                continue
        if not resolved.exists():
            problems.append((number, target, "no such file"))
            continue
        if fragment and resolved.suffix == ".md" and resolved.is_file():
            if fragment.lower() not in anchors(resolved):
                problems.append((number, target, f"no heading #{fragment} in {resolved.name}"))
    return problems


def closure(paths):
    """Every existing local file that the Markdown files PATHS link to, following the links of
    the linked Markdown files too (the files themselves included), sorted."""
    seen = set()
    pending = [pathlib.Path(p).resolve() for p in paths]
    while pending:
        path = pending.pop()
        if path in seen or not path.is_file():
            continue
        seen.add(path)
        if path.suffix != ".md":
            continue
        pending += [resolve(path, target)[0]
                    for _, target in relative_links(path.read_text(encoding="utf-8"))]
    return sorted(seen)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="*", help="default: README.md, docs/*.md, core/**/README.md, bench/results/*.md")
    parser.add_argument("--inside", help="also fail links that leave this folder")
    parser.add_argument("--closure", action="store_true",
                        help="print the local files the given Markdown files link to")
    args = parser.parse_args()
    if args.closure:
        for path in closure(args.files):
            print(os.path.relpath(path, REPO))
        return
    files = ([pathlib.Path(f) for f in args.files] or
             [REPO / "README.md"] + sorted((REPO / "docs").glob("*.md")) +
             sorted((REPO / "core").glob("**/README.md")) +
             sorted((REPO / "bench" / "results").glob("*.md")))
    problems = 0
    checked = 0
    for path in files:
        checked += len(relative_links(path.read_text(encoding="utf-8")))
        for number, target, reason in broken(path, args.inside):
            shown = os.path.relpath(path) if path.is_absolute() else path
            print(f"{shown}:{number}: {target}: {reason}", file=sys.stderr)
            problems += 1
    if problems:
        sys.exit(f"check-links: {problems} broken link(s) of {checked} in {len(files)} file(s)")
    print(f"check-links: {checked} relative links in {len(files)} files resolve")


if __name__ == "__main__":
    main()
