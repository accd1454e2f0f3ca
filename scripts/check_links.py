#!/usr/bin/env python3
"""Every relative link in the repository's Markdown resolves: the file exists and, where
the link names a section (`page.md#a-heading`), the page has that heading (GitHub's
anchors: lower case, punctuation dropped, spaces as hyphens, repeats numbered).

Usage: scripts/check_links.py [FILE.md ...]   (default: every tracked .md file)
Exit status 1 if a link is broken; each is printed as FILE:LINE: LINK (why).
"""
import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LINK = re.compile(r"\]\(([^)\s]+)\)")
FENCE = re.compile(r"^\s*```")


def anchor(heading: str) -> str:
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def anchors(page: Path) -> set[str]:
    found, seen, fenced = set(), {}, False
    for line in page.read_text().splitlines():
        fenced ^= bool(FENCE.match(line))
        heading = None if fenced else re.match(r"^#+\s+(.*)", line)
        if heading:
            name = anchor(heading.group(1))
            n = seen.get(name, 0)
            found.add(name if n == 0 else f"{name}-{n}")
            seen[name] = n + 1
    return found


def broken(page: Path, cache: dict) -> list[str]:
    """The broken links of `page`, each as LINE: LINK (why)."""
    problems, fenced = [], False
    for number, line in enumerate(page.read_text().splitlines(), 1):
        fenced ^= bool(FENCE.match(line))
        if fenced:
            continue
        for link in LINK.findall(line):
            if re.match(r"^[a-z][a-z0-9+.-]*:", link):  # http:, mailto: ...
                continue
            path, _, section = link.partition("#")
            target = (page.parent / path).resolve() if path else page
            if not target.exists():
                problems.append(f"{number}: {link} (no such file)")
            elif section and target.suffix == ".md":
                if target not in cache:
                    cache[target] = anchors(target)
                if section not in cache[target]:
                    problems.append(f"{number}: {link} (no such heading in {target.name})")
    return problems


def main(argv: list[str]) -> int:
    if argv:
        pages = [Path(a).resolve() for a in argv]
    else:
        listed = subprocess.run(["git", "ls-files", "*.md"], cwd=ROOT, check=True,
                                capture_output=True, text=True).stdout.split()
        pages = [ROOT / p for p in listed]
    cache, count = {}, 0
    for page in pages:
        for problem in broken(page, cache):
            print(f"{os.path.relpath(page, ROOT)}:{problem}")
            count += 1
    print(f"{len(pages)} pages, {count} broken links")
    return 1 if count else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
