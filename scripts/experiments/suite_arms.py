"""The suite's methods as its tables name them: one list for suite.py, which writes the
tables, and scripts/check_results.py, which checks them (and imports nothing heavy)."""

# A method's folder under <task>/runs and its name in the tables.
ARM_NAMES = {
    "logo": "LOGO (new-task preset)",
    "logo-decayed": "LOGO, δ_k decaying",
    "logo-waiting": "LOGO, δ_k waiting for 0.9 of the batch at the goal",
    "logo-eval-waiting": "LOGO, δ_k waiting for 0.9 of the evaluation at the goal",
    "logo-eval-following": "LOGO, δ_k following the evaluation's 0.9 at the goal",
    "trpo": "TRPO",
    "gail": "GAIL",
    "pofd": "POfD",
    "bc-trpo": "BC-TRPO",
    "dapg": "DAPG",
    "bc": "BC",
}
