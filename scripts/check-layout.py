#!/usr/bin/env python3
"""The layout rules of core/ (docs/architecture.md), checked so that they cannot slip:

  1. no function in core/ is longer than 80 lines (signature to closing brace);
  2. every include follows the layer order common <- linear <- paper <- refine <- root
     (parameterize.*) <- atlas: a file includes its own layer or a lower one, never a higher one
     (so the paper's folder includes nothing of the refinement's);
  3. one pi for all of core/ (kPi in core/common/geometry.h): no M_PI, no other pi literal.

usage: python3 scripts/check-layout.py [--root DIR]   (exit 1 and one line per breach)"""
import argparse
import pathlib
import re
import sys

MAX_FUNCTION_LINES = 80
LAYERS = ["common", "linear", "paper", "refine", "root", "atlas"]
PI_HOME = "common/geometry.h"


def layer_of(relative):  # relative to core/
    parts = pathlib.PurePosixPath(relative).parts
    return parts[0] if len(parts) > 1 else "root"


def code_only(text):
    """The text with comments, string and character literals blanked (newlines kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        two = text[i:i + 2]
        if two == "//":
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif two == "/*":
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text[i] in "\"'":
            quote, j = text[i], i + 1
            while j < n and text[j] != quote:
                j += 2 if text[j] == "\\" else 1
            out.append(quote + " " * (j - i - 1) + quote)
            i = j + 1
        else:
            out.append(text[i])
            i += 1
    return "".join(out)


def long_functions(text):
    """(first line, lines) of every function body longer than the limit."""
    code = code_only(text)
    found, stack = [], []  # stack of (kind, start line)
    header_start = 0  # offset where the text before the next '{' began
    line = 1
    for i, c in enumerate(code):
        if c == "\n":
            line += 1
        if c not in "{};":
            continue
        inside_function = any(kind == "function" for kind, _ in stack)
        if c == "{":
            header = code[header_start:i]
            if inside_function:
                kind = "block"
            elif re.search(r"\bnamespace\b", header) or re.search(r'extern\s+" *"', header):
                kind = "namespace"
            elif "(" in header and not re.search(r"=\s*$|=\s*[^=]*$", header.split("(")[0]):
                kind = "function"
            else:
                kind = "other"  # types, enums, brace initializers
            first = code.count("\n", 0, header_start) + 1
            first += len(header) - len(header.lstrip("\n \t")) and header[:len(header) - len(header.lstrip())].count("\n")
            stack.append((kind, first))
        elif c == "}" and stack:
            kind, first = stack.pop()
            if kind == "function" and line - first + 1 > MAX_FUNCTION_LINES:
                found.append((first, line - first + 1))
        if not inside_function or c == "}":
            header_start = i + 1
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", default=pathlib.Path(__file__).resolve().parent.parent)
    core = pathlib.Path(parser.parse_args().root) / "core"
    breaches = []
    include = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
    for path in sorted(core.rglob("*")):
        if path.suffix not in (".h", ".cpp"):
            continue
        relative = path.relative_to(core).as_posix()
        text = path.read_text()
        own = layer_of(relative)
        for target in include.findall(text):
            if target.startswith("core/"):
                target_layer = layer_of(target[len("core/"):])
            else:
                target_layer = own  # a bare include is a file of the same folder
            if LAYERS.index(target_layer) > LAYERS.index(own):
                breaches.append(f"core/{relative}: includes {target} ({target_layer}), above its "
                                f"layer ({own}); order: {' <- '.join(LAYERS)}")
        for first, lines in long_functions(text):
            breaches.append(f"core/{relative}:{first}: function of {lines} lines "
                            f"(at most {MAX_FUNCTION_LINES})")
        code = code_only(text)
        for number, code_line in enumerate(code.splitlines(), 1):
            if re.search(r"\bM_PI\b|\bacos\s*\(\s*-\s*1|3\.14159", code_line) and not (
                    relative == PI_HOME and "kPi" in code_line):
                breaches.append(f"core/{relative}:{number}: a pi of its own: use kPi "
                                f"(core/{PI_HOME})")
    for breach in breaches:
        print(breach)
    print(f"check-layout: {len(breaches)} breach(es) in {core}", file=sys.stderr)
    return 1 if breaches else 0


if __name__ == "__main__":
    sys.exit(main())
