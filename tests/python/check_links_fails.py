"""scripts/check_links.py can fail: a missing file, a missing heading on this page or on
another, each found; a link inside a code block, or to a web address, left alone. Run by
scripts/test.sh; exits non-zero if the checker misses one or flags a good link."""

import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PAGE = """# A page

## Findings, one line: each

[good](#findings-one-line-each) [good file](other.md) [good heading](other.md#there)
[web](https://example.org/x.md)
[missing heading](#nowhere) [missing file](absent.md) [missing there](other.md#elsewhere)

```
[in a code block](absent-too.md)
```
"""


def main():
    with tempfile.TemporaryDirectory() as tmp:
        page, other = Path(tmp) / "page.md", Path(tmp) / "other.md"
        page.write_text(PAGE)
        other.write_text("# There\n")
        run = subprocess.run([sys.executable, str(ROOT / "scripts/check_links.py"), str(page)],
                             capture_output=True, text=True)
    # Every line but the last (the count) names one broken link.
    flagged = run.stdout.splitlines()[:-1]
    wanted = ["#nowhere", "absent.md (", "other.md#elsewhere"]
    missed = [w for w in wanted if not any(w in line for line in flagged)]
    wrong = [line for line in flagged if not any(w in line for w in wanted)]
    print(f"check_links: {len(wanted) - len(missed)} of {len(wanted)} broken links found, "
          f"{len(wrong)} good ones flagged")
    if run.returncode != 1 or missed or wrong:
        print(run.stdout, run.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
