"""scripts/check_results.py can fail: a wrong cell, a table without a source, a source
that does not exist. Run by scripts/test.sh; exits non-zero if the checker misses one."""

import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
GOOD = """<!-- check summary rows=four-envs/hopper/logo-hopper -->
| configuration | seeds | final | at 2M |
| --- | --- | --- | --- |
| LOGO | 3 | 1617 ± 931 | 1611 ± 920 |
"""


def check(text):
    with tempfile.TemporaryDirectory() as tmp:
        doc = Path(tmp) / "results.md"
        doc.write_text(text)
        run = subprocess.run([sys.executable, str(ROOT / "scripts/check_results.py"), str(doc)],
                             capture_output=True, text=True)
        return run.returncode, run.stdout


def main():
    failures = []
    code, out = check(GOOD)
    if code != 0:
        failures.append(f"a correct table failed:\n{out}")
    cases = {
        "a wrong mean": GOOD.replace("1617 ± 931", "1618 ± 931"),
        "a wrong std": GOOD.replace("1611 ± 920", "1611 ± 922"),
        "a wrong count": GOOD.replace("| 3 |", "| 4 |"),
        "a table without its source": GOOD.split("\n", 1)[1],
        "a source that does not exist": GOOD.replace("logo-hopper", "no-such-group"),
        "an unknown column": GOOD.replace("| at 2M |", "| median of something |"),
    }
    for name, text in cases.items():
        code, out = check(text)
        if code == 0:
            failures.append(f"{name} passed:\n{out}")
    if failures:
        print("\n".join(failures))
        return 1
    print(f"check_results.py: a correct table passes, {len(cases)} wrong ones fail")
    return 0


if __name__ == "__main__":
    sys.exit(main())
