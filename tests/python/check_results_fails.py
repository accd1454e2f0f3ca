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

# An outside curve's row and a column read as the mean of the 10 nearest evaluations.
WINDOWED = """<!-- check summary rows=four-envs/hopper/logo-hopper;reference-curves/Hopper_LOGO_ref.csv@rewards/eval_R_avg -->
| configuration | seeds | at 1.00M, mean of 10 | at 10.00M, mean of 10 |
| --- | --- | --- | --- |
| LOGO | 3 | 1108 ± 91 | — |
| reference code | 1 | 51 ± 0 | 2145 ± 0 |
"""
# A run's 20-episode `logo eval` output.
EVALS = """<!-- check evals runs=paper-scale/hopper/hopper/seed1 -->
| run | dense return (20 episodes) | length | action RMS |
| --- | --- | --- | --- |
| seed 1 | 3118 ± 24 | 1000 | 1.37 |
"""

# The env's own return, the first field of a `logo eval` line (sparse on a sparse env).
EVALS_OWN = """<!-- check evals runs=paper-scale/hopper/hopper/seed1 -->
| run | sparse return (20 episodes) | x moved |
| --- | --- | --- |
| seed 1 | 3118 ± 24 | 16.99 ± 0.19 |
"""

# Another `logo eval` output kept beside eval-20.txt (here with --clip-actions).
CLIPPED = """<!-- check evals runs=paper-scale/halfcheetah/logo-halfcheetah/seed0 file=eval-20-clipped.txt -->
| run | dense return (20 episodes) | x moved | action RMS |
| --- | --- | --- | --- |
| seed 0 | 1467 ± 763 | 92.73 ± 36.54 | 0.80 |
"""

# Window means per seed: one run's row is its bare mean, no spread.
ONE_RUN_WINDOWS = """<!-- check windows rows=paper-scale/halfcheetah/logo-halfcheetah/seed0 cols=eval_action_rms:300-399 -->
| run | action RMS, 300–399 |
| --- | --- |
| seed 0 | 1.55 |
"""

# Ahead, behind or mixed against the reference curve at equal samples.
REF = "reference-curves/Hopper_LOGO_ref.csv@rewards/eval_R_avg"
VERDICTS = f"""<!-- check verdicts seeds=3 window=10 rows=paper-scale/hopper/hopper>{REF};->{REF} -->
| env | configuration | 2M | 10M |
| --- | --- | --- | --- |
| Hopper | LOGO | ahead (1677 vs 50) | mixed, 2 of 3 above (2518 vs 2145) |
| Hopper | not run | — | — |
"""

# `logo summary`'s interval table: points exact, interval ends near a bootstrap's.
INTERVALS = """<!-- check intervals window=10 rows=paper-scale/hopper/hopper -->
| configuration | seeds | final: mean [95% CI] | at 10.00M: IQM [95% CI] |
| --- | --- | --- | --- |
| LOGO | 3 | 2554 [1612, 3120] | 2518 [1441, 3141] |
"""

# `logo summary --compare A B`: P(A > B) and the IQM difference per budget.
COMPARE = """<!-- check compare window=10 groups=five-seeds-view/hopper/LOGO;five-seeds-view/hopper/LOGO+PPO+CDQ -->
| budget | seeds | P(LOGO > LOGO+PPO+CDQ) [95% CI] | IQM difference [95% CI] |
| --- | --- | --- | --- |
| final | 5 vs 5 | 0.80 [0.44, 1.00] | 963 [-335, 2183] |
| at 2.00M, mean of 10 | 5 vs 5 | 1.00 [1.00, 1.00] | 1549 [896, 2207] |
"""

# Arms against a baseline, each row at its own budget and window.
ARMS = """<!-- check arms rows=five-seeds-view/walker2d/LOGO@10M:10;five-seeds-view/walker2d/LOGO+PPO+CDQ>five-seeds-view/walker2d/LOGO@10M:10 -->
| env | budget | configuration | seeds | IQM [95% CI] | P(configuration > LOGO) [95% CI] | IQM difference [95% CI] |
| --- | --- | --- | --- | --- | --- | --- |
| Walker2d | 10M | LOGO | 5 | 2593 [1841, 3511] | — | — |
| Walker2d | 10M | LOGO+PPO+CDQ | 5 | 507 [403, 1376] | 0.04 [0.00, 0.24] | -2086 [-2998, -940] |
"""

# `logo summary`'s end-of-run table from each seed's eval.json.
EVALJSON = """<!-- check evaljson rows=python-idp -->
| configuration | runs | final: return [95% CI] | final: dense return [95% CI] | final: dense, clipped [95% CI] | best: return [95% CI] | best: dense return [95% CI] | final: success | best: success |
| --- | --- | --- | --- | --- | --- | --- | --- | --- |
| python-idp | 5 | 7406 [4763, 9003] | 7406 [4763, 9003] | 7406 [4763, 9003] | 7517 [4447, 9270] | 7517 [4447, 9270] | 100% | 100% |
"""

# An interval table of another metrics.csv column (`logo summary --metric`).
METRIC_INTERVALS = """<!-- check intervals window=5 rows=python-idp@train_sparse_return -->
| configuration | seeds | final: mean [95% CI] | final: IQM [95% CI] |
| --- | --- | --- | --- |
| python-idp | 5 | 7595 [4672, 9357] | 8855 [3984, 9357] |
"""

# Episodes at the goal per seed (a task that ends only there) from eval.json.
GOAL = """<!-- check goal rows=new-task-mcc/template -->
| arm | seeds | final: episodes at the goal, per seed | final: seeds with all episodes | best: episodes at the goal, per seed |
| --- | --- | --- | --- | --- |
| old template | 5 | 0, 0, 0, 0, 0 | 0 | 8, 20, 0, 20, 20 |
"""

# A settings table against the TOML file it describes.
CONFIG = """<!-- check config file=configs/templates/new_task.toml -->
| setting | value |
| --- | --- |
| `[guidance] delta0` | 0.01 |
| `success` | `"task"` |
"""

# Two groups at a budget, one of them an outside curve's folder of CSVs, with a verdict.
VERSUS = """<!-- check versus rows=variants-idp/logo-inverted_double_pendulum>reference-curves/v4/idp@200k:5 -->
| task | budget | logo-rl: IQM [95% CI] | seeds | reference: IQM [95% CI] | seeds | P(logo-rl > reference) [95% CI] | IQM difference [95% CI] | verdict |
| --- | --- | --- | --- | --- | --- | --- | --- | --- |
| sparse IDP | 200k | 8033 [4536, 9354] | 5 | 8994 [4225, 9342] | 5 | 0.52 [0.00, 0.88] | −961 [−4092, 3996] | cannot separate |
"""

# A suite task's final policies (suite.py report): goals per seed, the target, P and IQMs.
SUITE = """<!-- check suite rows=suite/reacher-goal/logo-decayed;suite/reacher-goal/trpo;suite/reacher-goal/bc demos=20/20 -->
| method | seeds | final return: IQM [95% CI] | reached the goal, final policy per seed | seeds at ≥ the demonstrations' 20/20 | P(LOGO > method) [95% CI] | IQM difference LOGO − method [95% CI] |
| --- | --- | --- | --- | --- | --- | --- |
| LOGO, δ_k decaying | 5 | 41.8 [41.0, 42.0] | 20, 20, 20, 20, 20 of 20 | 5 of 5 | — | — |
| TRPO | 5 | 41.5 [39.2, 41.9] | 20, 20, 20, 20, 20 of 20 | 5 of 5 | 0.60 [0.20, 1.00] | 0.2 [−0.5, 2.5] |
| BC | 5 | 1.9 [0.9, 2.4] | 6, 4, 4, 8, 9 of 20 | 0 of 5 | 1.00 [1.00, 1.00] | 39.9 [39.0, 40.8] |
"""

# The suite's target per task: seeds at the demonstrations, P(LOGO > TRPO), the verdict.
TARGET = """<!-- check target rows=suite/reacher-goal/logo>suite/reacher-goal/trpo;suite/maze/logo-decayed>suite/maze/trpo;suite/hopper-delayed/logo>suite/hopper-delayed/trpo quoted=6 -->
| task | LOGO | seeds at ≥ the demonstrations | P(LOGO > TRPO) [95% CI] | target | why |
| --- | --- | --- | --- | --- | --- |
| `reacher-goal` | LOGO (new-task preset) | 4 of 5 | 0.16 [0.00, 0.48] | not met: TRPO | a reading |
| `maze` | LOGO, δ_k decaying | 5 of 5 | 1.00 [1.00, 1.00] | met | — |
| `hopper-delayed` | LOGO (new-task preset) | 1 of 5 | 1.00 [1.00, 1.00] | not met: the demonstrations | a reading |
"""

# A grid of verdicts: IQM differences at a budget, the verdict from the interval.
MATRIX = """<!-- check matrix rows=fig1-idp/logo@200k:5+;new-task/ant/runs/logo@2M:10 r1c2=fig1-idp/gail r1c3=fig1-idp/trpo r2c2=fig1-ant/gail -->
| LOGO against | GAIL | TRPO |
| --- | --- | --- |
| sparse IDP (5 seeds × 200k) | cannot separate −1276 [−4336, 484] | ahead 7699 [4207, 9022] |
| sparse Ant (3 × 2M) | behind, suggests −343 [−574, −112] | — |
"""

# The README's answer: each method's IQM on a row, the leader and whom its interval puts it
# ahead of, level with or cannot separate it from; the section's prose within its words.
ANSWER = """## Does it work?

Two rows of the README's table.

<!-- check answer prose=20 rows=final=suite/reacher-goal/logo,suite/reacher-goal/trpo,suite/reacher-goal/bc,-;final=suite/mountain-car-degraded/logo,suite/mountain-car/trpo,suite/mountain-car-degraded/bc,suite/mountain-car-degraded/dapg -->
| task | measure | LOGO | TRPO | BC | DAPG | who leads |
| --- | --- | --- | --- | --- | --- | --- |
| Reacher | final policies' return | 39.7 | 41.5 | 1.8 | — | **TRPO**; ahead of BC; level with LOGO |
| MountainCarContinuous, degraded | final policies' return | 96.9 | 62.3 | −0.4 | 96.3 | **LOGO**; ahead of BC; cannot separate from TRPO, DAPG |
"""


def check(text):
    with tempfile.TemporaryDirectory() as tmp:
        doc = Path(tmp) / "results.md"
        doc.write_text(text)
        run = subprocess.run([sys.executable, str(ROOT / "scripts/check_results.py"), str(doc)],
                             capture_output=True, text=True)
        return run.returncode, run.stdout


# Runs kept compressed (metrics.csv.gz, eval.json.gz) read as the plain ones: copies of
# SUITE's and VERSUS's groups, gzip-compressed, under a scratch folder of docs/results.
PACKED = ".check-results-gz"


def packed_copies():
    import gzip
    import shutil
    scratch = ROOT / "docs/results" / PACKED
    for group in ("suite/reacher-goal/logo-decayed", "suite/reacher-goal/trpo",
                  "suite/reacher-goal/bc", "variants-idp/logo-inverted_double_pendulum"):
        for source in (ROOT / "docs/results" / group).glob("seed*/*"):
            dest = scratch / group / source.parent.name / source.name
            dest.parent.mkdir(parents=True, exist_ok=True)
            if source.name in ("metrics.csv", "eval.json", "policy.eval.json"):
                with open(source, "rb") as f, gzip.open(f"{dest}.gz", "wb") as g:
                    shutil.copyfileobj(f, g)
            else:
                shutil.copy(source, dest)
    return scratch


def main():
    failures = []
    scratch = packed_copies()
    try:
        packed = (SUITE.replace("rows=suite/", f"rows={PACKED}/suite/").replace(";suite/", f";{PACKED}/suite/"),
                  VERSUS.replace("rows=variants-idp/", f"rows={PACKED}/variants-idp/"))
        for good in packed:
            code, out = check(good)
            if code != 0 or PACKED not in good:
                failures.append(f"a correct table of compressed runs failed:\n{out}")
        code, _ = check(packed[0].replace("41.5 [39.2", "41.4 [39.2"))
        if code == 0:
            failures.append("a wrong IQM of compressed runs passed")
    finally:
        import shutil
        shutil.rmtree(scratch, ignore_errors=True)
    goods = (GOOD, WINDOWED, EVALS, VERDICTS, ONE_RUN_WINDOWS, CLIPPED, INTERVALS, COMPARE, ARMS,
             EVALJSON, METRIC_INTERVALS, EVALS_OWN, GOAL, CONFIG, VERSUS, SUITE, TARGET, MATRIX,
             ANSWER)
    for good in goods:
        code, out = check(good)
        if code != 0:
            failures.append(f"a correct table failed:\n{out}")
    cases = {
        "a wrong windowed std": WINDOWED.replace("1108 ± 91", "1108 ± 92"),
        "an outside curve's wrong value": WINDOWED.replace("2145 ± 0", "2173 ± 0"),
        "a value where the runs stop short": WINDOWED.replace("| — |", "| 1601 ± 920 |"),
        "an outside curve's wrong column": WINDOWED.replace("@rewards/eval_R_avg", "@KL"),
        "a wrong window mean of one run": ONE_RUN_WINDOWS.replace("| 1.55 |", "| 1.54 |"),
        "a spread on one run's window mean": ONE_RUN_WINDOWS.replace("| 1.55 |", "| 1.55 ± 0.1 |"),
        "a wrong 20-episode mean": EVALS.replace("3118 ± 24", "3120 ± 24"),
        "a wrong episode length": EVALS.replace("| 1000 |", "| 999 |"),
        "the unclipped evaluation's numbers": CLIPPED.replace("1467 ± 763", "537 ± 1931"),
        "a missing eval file": EVALS.replace("seed1 -->", "seed1 file=eval-20-clipped.txt -->"),
        "a wrong interval mean": INTERVALS.replace("2554 [", "2560 ["),
        "a wrong interval end": INTERVALS.replace("[1441, 3141]", "[1200, 3141]"),
        "a column summary does not print": INTERVALS.replace("IQM [95% CI]", "median [95% CI]"),
        "a wrong own return": EVALS_OWN.replace("3118 ± 24", "3118 ± 25"),
        "a wrong end-of-run mean": EVALJSON.replace("7517 [4447, 9270] | 7517", "7527 [4447, 9270] | 7517"),
        "a wrong end-of-run interval": EVALJSON.replace("7406 [4763, 9003] |", "7406 [4000, 9003] |", 1),
        "a wrong success rate": EVALJSON.replace("100% | 100%", "80% | 100%"),
        "a wrong count of eval.json runs": EVALJSON.replace("| 5 |", "| 4 |"),
        "an eval.json table of a group without them": EVALJSON.replace("rows=python-idp", "rows=five-seeds-view/hopper/LOGO"),
        "another column's intervals": METRIC_INTERVALS.replace("@train_sparse_return", ""),
        "a wrong probability of improvement": COMPARE.replace("0.80 [", "0.76 ["),
        "a wrong IQM difference's interval": COMPARE.replace("[896, 2207]", "[500, 2207]"),
        "the groups compared the other way": COMPARE.replace(
            "LOGO;five-seeds-view/hopper/LOGO+PPO+CDQ", "LOGO+PPO+CDQ;five-seeds-view/hopper/LOGO"),
        "an arm's wrong IQM": ARMS.replace("507 [", "517 ["),
        "an arm's wrong seed count": ARMS.replace("| 5 | 507", "| 4 | 507"),
        "a baseline row with a probability": ARMS.replace("| — | — |", "| 0.50 [0.00, 1.00] | — |"),
        "an arm's wrong P interval": ARMS.replace("[0.00, 0.24]", "[0.00, 0.64]"),
        "an arm at the wrong budget": ARMS.replace("LOGO@10M:10 -->", "LOGO@5M:10 -->"),
        "a wrong verdict": VERDICTS.replace("ahead (1677", "behind (1677"),
        "a wrong count of seeds above": VERDICTS.replace("2 of 3", "1 of 3"),
        "a wrong mean beside a verdict": VERDICTS.replace("2518 vs", "2600 vs"),
        "a verdict on a row without runs": VERDICTS.replace("| not run | — |", "| not run | ahead (1 vs 50) |"),
        "a verdict with fewer seeds than named": VERDICTS.replace("seeds=3", "seeds=4"),
        "a wrong mean": GOOD.replace("1617 ± 931", "1618 ± 931"),
        "a wrong std": GOOD.replace("1611 ± 920", "1611 ± 922"),
        "a wrong count": GOOD.replace("| 3 |", "| 4 |"),
        "a table without its source": GOOD.split("\n", 1)[1],
        "a source that does not exist": GOOD.replace("logo-hopper", "no-such-group"),
        "an unknown column": GOOD.replace("| at 2M |", "| median of something |"),
        "a wrong count at the goal": GOAL.replace("8, 20, 0, 20, 20", "8, 20, 0, 20, 19"),
        "a wrong count of seeds at the goal": GOAL.replace("| 0 | 8,", "| 1 | 8,"),
        "a goal table's seeds in another order": GOAL.replace("8, 20, 0, 20, 20", "20, 20, 20, 8, 0"),
        "a wrong reference IQM": VERSUS.replace("8994 [", "8894 ["),
        "a wrong reference seed count": VERSUS.replace("| 5 | 0.52", "| 4 | 0.52"),
        "a verdict the interval does not support": VERSUS.replace("| cannot separate |", "| level |"),
        "a verdict by the old fixed-width rule": VERSUS.replace("| cannot separate |", "| unresolved |"),
        "a P interval end outside the bootstrap's band": VERSUS.replace("[0.00, 0.88]", "[0.00, 0.60]"),
        "rows read up to the budget, the cells not": VERSUS.replace("check versus rows", "check versus max=budget rows"),
        "a wrong difference interval": VERSUS.replace("[−4092, 3996]", "[−4092, −100]"),
        "a wrong setting": CONFIG.replace("| 0.01 |", "| 0.2 |"),
        "a setting the file lacks": CONFIG.replace("[guidance] delta0", "[guidance] delta"),
        "a wrong word setting": CONFIG.replace('`"task"`', '`"terminated"`'),
        "a suite task's wrong goal count": SUITE.replace("6, 4, 4, 8, 9", "6, 4, 4, 8, 8"),
        "a suite task's wrong IQM": SUITE.replace("41.5 [39.2", "41.4 [39.2"),
        "a suite task's wrong P": SUITE.replace("0.60 [0.20", "0.64 [0.20"),
        "a suite task's wrong count at the target": SUITE.replace("| 0 of 5 |", "| 1 of 5 |"),
        "a suite task's target other than its comment's": SUITE.replace("demonstrations' 20/20 |", "demonstrations' 19/20 |"),
        "a suite task's rows swapped": SUITE.replace("| TRPO | 5 |", "| BC | 5 |", 1),
        "a suite task's P on LOGO's own row": SUITE.replace("| 5 of 5 | — | — |", "| 5 of 5 | 0.50 [0.00, 1.00] | — |"),
        "a target met where P's interval holds 0.5": TARGET.replace("| not met: TRPO |", "| met |"),
        "a target met short of the demonstrations": TARGET.replace("| not met: the demonstrations |", "| met |"),
        "a target's wrong seed count": TARGET.replace("| 4 of 5 |", "| 5 of 5 |"),
        "a target's P against another method": TARGET.replace("reacher-goal/trpo;", "reacher-goal/bc;"),
        "a target's wrong arm": TARGET.replace("| LOGO, δ_k decaying |", "| LOGO (new-task preset) |"),
        "a target against another task's TRPO": TARGET.replace("hopper-delayed/trpo", "maze/trpo"),
        "a target with an unnamed column": TARGET.replace(" quoted=6", ""),
        "a target read from the final policies, the best named": TARGET.replace("check target", "check target policy=best"),
        "a grid's verdict the interval does not give": MATRIX.replace("cannot separate −1276", "level −1276"),
        "a grid's cell without its few seeds said": MATRIX.replace("behind, suggests", "behind"),
        "a grid's wrong difference": MATRIX.replace("7699 [", "7600 ["),
        "a grid read up to the budget, its cells not": MATRIX.replace("200k:5+;", "200k:5;"),
        "a grid's value where no cell is named": MATRIX.replace("| — |", "| ahead 28 [−124, 246] |"),
        "a grid's verdict from an end printed across 0": MATRIX.replace("behind, suggests −343 [−574, −112]", "level, suggests −343 [−574, 5]"),
        "a grid's row label with other seeds": MATRIX.replace("(3 × 2M)", "(5 × 2M)"),
        "a grid's columns named the other way": MATRIX.replace("| LOGO against | GAIL | TRPO |", "| LOGO against | TRPO | GAIL |"),
        "a grid's text after the interval": MATRIX.replace("[4207, 9022] |", "[4207, 9022] over 9 seeds |"),
        "a grid's cell outside the table": MATRIX.replace(" -->", " r3c2=fig1-idp/gail -->", 1),
        "a grid with the level= it no longer reads": MATRIX.replace(" -->", " level=10000 -->", 1),
        "a target whose demonstrations it does not meet": TARGET.replace("| not met: the demonstrations |", "| not met: both |"),
        "a target against another arm of the task": TARGET.replace("maze/trpo", "maze/logo"),
        "a target's reading checked as quoted": TARGET.replace("quoted=6", "quoted=4,6"),
        "a suite table with an option it does not read": SUITE.replace("check suite", "check suite policy=best"),
        "a versus table with an option it does not read": VERSUS.replace("check versus", "check versus level=5000"),
        "an answer's wrong IQM": ANSWER.replace("| 39.7 |", "| 39.9 |"),
        "an answer's wrong leader": ANSWER.replace("**TRPO**; ahead of BC; level with LOGO", "**LOGO**; ahead of BC; level with TRPO"),
        "an answer's level that its interval puts ahead": ANSWER.replace("**TRPO**; ahead of BC; level with LOGO", "**TRPO**; ahead of BC, LOGO"),
        "an answer's leader ahead of one its interval cannot separate": ANSWER.replace("ahead of BC; cannot separate from TRPO, DAPG", "ahead of BC, TRPO; cannot separate from DAPG"),
        "an answer that leaves out whom it cannot separate": ANSWER.replace("; cannot separate from TRPO, DAPG", ""),
        "an answer's level where the interval is wide": ANSWER.replace("cannot separate from TRPO, DAPG", "level with TRPO, DAPG"),
        "an answer's value where no group is named": ANSWER.replace("| 1.8 | — |", "| 1.8 | 41.1 |"),
        "an answer whose prose is over its words": ANSWER.replace("Two rows of the README's table.", "Two rows of the README's table, and after them a good many more words than the twenty that the check allows this section here."),
        "an answer's columns named the other way": ANSWER.replace("| LOGO | TRPO | BC |", "| TRPO | LOGO | BC |"),
        "a grid's cells swapped": MATRIX.replace("r1c2=fig1-idp/gail r1c3=fig1-idp/trpo", "r1c2=fig1-idp/trpo r1c3=fig1-idp/gail"),
    }
    for name, text in cases.items():
        code, out = check(text)
        if code == 0:
            failures.append(f"{name} passed:\n{out}")
    if failures:
        print("\n".join(failures))
        return 1
    print(f"check_results.py: {len(goods)} correct tables pass, {len(cases)} wrong ones fail")
    return 0


if __name__ == "__main__":
    sys.exit(main())
