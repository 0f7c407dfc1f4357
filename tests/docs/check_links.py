#!/usr/bin/env python3
"""Every relative link in README.md, CHANGELOG.md and docs/**/*.md resolves.

    check_links.py SOURCE_DIR

A link is [text](target) or ![alt](target); web addresses (scheme:...) and
anchors within the page (#...) are not checked, a target's own #anchor is
dropped. Links inside code (``` blocks and `spans`) are not links. Prints
each broken link as FILE:LINE: target and exits 1 if there is one: a doc
that points at a moved or renamed file sends the reader nowhere.
"""
import pathlib
import re
import sys

LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
SPAN = re.compile(r"`[^`]*`")


def pages(root):
    yield root / "README.md"
    if (root / "CHANGELOG.md").exists():
        yield root / "CHANGELOG.md"
    yield from sorted((root / "docs").rglob("*.md"))


def broken(root, page):
    in_code = False
    for n, line in enumerate(page.read_text(encoding="utf-8").splitlines(), 1):
        if line.lstrip().startswith("```"):
            in_code = not in_code
            continue
        if in_code:
            continue
        for target in LINK.findall(SPAN.sub("", line)):
            if re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", target) or target.startswith("#"):
                continue
            path = target.split("#", 1)[0]
            resolved = (root / path.lstrip("/")) if path.startswith("/") else (page.parent / path)
            if not resolved.exists():
                yield n, target


def main():
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    root = pathlib.Path(sys.argv[1]).resolve()
    bad = 0
    checked = 0
    for page in pages(root):
        checked += 1
        for n, target in broken(root, page):
            print(f"{page.relative_to(root)}:{n}: {target}")
            bad += 1
    print(f"{checked} pages, {bad} broken links")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
