"""The suite's methods as its tables name them, and its demonstrations' figures: one copy
for suite.py, which writes the tables, and scripts/check_results.py, which checks them
(and imports nothing heavy)."""

# A method's folder under <task>/runs and its name in the tables.
ARM_NAMES = {
    "logo": "LOGO (new-task preset)",
    "logo-decayed": "LOGO, δ_k decaying",
    "logo-waiting": "LOGO, δ_k waiting for 0.9 of the batch at the goal",
    "logo-eval-waiting": "LOGO, δ_k waiting for 0.9 of the evaluation at the goal",
    "logo-eval-following": "LOGO, δ_k following the evaluation's 0.9 at the goal",
    "logo-letting-go": "LOGO, δ_k let go at the demonstrations' success",
    "bc-logo": "LOGO from the clone (new-task preset, [init] kind = \"bc\")",
    "bc-logo-letting-go": "LOGO from the clone, δ_k let go at the demonstrations' success",
    "trpo": "TRPO",
    "gail": "GAIL",
    "pofd": "POfD",
    "bc-trpo": "BC-TRPO",
    "dapg": "DAPG",
    "bc": "BC",
}


# The demonstrations' own figures, as `suite.py demos` printed them for the demonstrator
# (data/README.md's table; the same episodes, from the same initial states, as were
# recorded): episodes reaching the goal (None: the task has no goal) and the mean return.
DEMONSTRATED = {
    "reacher-goal": {"reached": (20, 20), "return": 29.70},
    "maze": {"reached": (20, 20), "return": 406.05},
    "mountain-car": {"reached": (15, 15), "return": 89.36},
    "ant-distance": {"reached": (19, 20), "return": 719.40},
    "hopper-delayed": {"reached": None, "return": 1381.50},
    # The degraded demonstrators (suite.py DEGRADED), as `suite.py demos` printed them.
    "reacher-goal-degraded": {"reached": (10, 20), "return": 1.05},
    "maze-degraded": {"reached": (7, 20), "return": 32.95},
    "mountain-car-degraded": {"reached": (8, 15), "return": 9.93},
}
