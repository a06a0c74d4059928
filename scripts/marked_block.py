"""Generated text between two marker lines of a Markdown file, such as
<!-- bench:atlas --> ... <!-- /bench:atlas -->: the one way the benches and the table scripts
rewrite or check the blocks they own in README.md and docs/*.md.

    replace_between(text, begin, end, body) -> text with the block's body replaced (None: no block)
    update_block(path, begin, end, body, check, stale_message) -> whether it was already current
"""
import pathlib
import sys


def replace_between(text, begin, end, body):
    """`text` with what lies between the first `begin` and the next `end` replaced by `body`
    (the markers kept); None when there is no such block."""
    start = text.find(begin)
    stop = text.find(end, start + len(begin)) if start >= 0 else -1
    if stop < 0:
        return None
    return text[:start + len(begin)] + body + text[stop:]


def update_block(path, begin, end, body, check, stale_message):
    """Writes `body` into the file's block, or with `check` only compares and exits with
    `stale_message` when it differs; exits naming the markers when the file has no block.
    Returns whether the block was already `body`."""
    path = pathlib.Path(path)
    text = path.read_text()
    replaced = replace_between(text, begin, end, body)
    if replaced is None:
        sys.exit(f"{path} has no {begin.strip()} ... {end.strip()} block")
    if replaced == text:
        return True
    if check:
        sys.exit(stale_message)
    path.write_text(replaced)
    return False
