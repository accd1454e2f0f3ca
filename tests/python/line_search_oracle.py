"""SciPy as the oracle for logo-rl's Moré–Thuente line search and its L-BFGS "strong-wolfe"
mode (crates/logo-algo/tests/line_search.rs). Prints JSON:

- "dcsrch": for each case (a test function of Moré & Thuente 1994, or Rosenbrock along
  its steepest descent, with a first step and tolerances), every step SciPy's port of
  MINPACK-2's dcsrch evaluates, in order, and the step it returns;
- "lbfgs": for each problem, the point, value and iteration count of
  scipy.optimize.fmin_l_bfgs_b (unbounded, maxiter 25: the LOGO reference's critic fit).
"""
import json
import math

import numpy as np
from scipy.optimize import fmin_l_bfgs_b
from scipy.optimize._dcsrch import DCSRCH


def mt1(a, beta=2.0):
    return -a / (a * a + beta), (a * a - beta) / (a * a + beta) ** 2


def mt2(a, beta=0.004):
    return (a + beta) ** 5 - 2 * (a + beta) ** 4, 5 * (a + beta) ** 4 - 8 * (a + beta) ** 3


def mt3(a, beta=0.01, l=39.0):
    if a <= 1 - beta:
        p0, d0 = 1 - a, -1.0
    elif a >= 1 + beta:
        p0, d0 = a - 1, 1.0
    else:
        p0, d0 = (a - 1) ** 2 / (2 * beta) + beta / 2, (a - 1) / beta
    c = 2 * (1 - beta) / (l * math.pi)
    return p0 + c * math.sin(l * math.pi * a / 2), d0 + (1 - beta) * math.cos(l * math.pi * a / 2)


def rosenbrock(x):
    x = np.asarray(x, dtype=float)
    f = float(np.sum(100.0 * (x[1:] - x[:-1] ** 2) ** 2 + (1 - x[:-1]) ** 2))
    g = np.zeros_like(x)
    g[:-1] += -400.0 * x[:-1] * (x[1:] - x[:-1] ** 2) - 2 * (1 - x[:-1])
    g[1:] += 200.0 * (x[1:] - x[:-1] ** 2)
    return f, g


def rosenbrock_line(a):
    x0 = np.array([-1.2, 1.0])
    _, g0 = rosenbrock(x0)
    d = -g0
    f, g = rosenbrock(x0 + a * d)
    return f, float(g @ d)


FUNCTIONS = {"mt1": mt1, "mt2": mt2, "mt3": mt3, "rosenbrock_line": rosenbrock_line}


def search(name, stp, ftol, gtol, xtol):
    fn = FUNCTIONS[name]
    steps = []

    def phi(a):
        steps.append(a)
        return fn(a)[0]

    def derphi(a):
        return fn(a)[1]

    f0, g0 = fn(0.0)
    stp_out, _, _, task = DCSRCH(phi, derphi, ftol, gtol, xtol, 0.0, 1e10)(stp, f0, g0, maxiter=100)
    task = task.decode() if isinstance(task, bytes) else str(task)
    return {"function": name, "first": stp, "ftol": ftol, "gtol": gtol, "xtol": xtol,
            "steps": steps, "result": stp_out, "task": task}


def quadratic():
    rng = np.random.default_rng(3)
    q = rng.uniform(-1, 1, (8, 8))
    a = q.T @ q + 0.1 * np.eye(8)
    b = rng.uniform(-1, 1, 8)
    return a, b


def lbfgs(name, x0):
    if name.startswith("rosenbrock"):
        fun = rosenbrock
    else:
        a, b = quadratic()
        fun = lambda x: (float(0.5 * x @ a @ x - b @ x), a @ x - b)
    x, f, info = fmin_l_bfgs_b(fun, np.array(x0, dtype=float), maxiter=25)
    return {"problem": name, "x0": x0, "x": x.tolist(), "f": f, "nit": info["nit"],
            "funcalls": info["funcalls"]}


cases = []
for name, first in [("mt1", 1e-3), ("mt1", 1e-1), ("mt1", 10.0), ("mt1", 1e3),
                    ("mt2", 1e-3), ("mt2", 1e-1), ("mt2", 10.0), ("mt2", 1e3),
                    ("mt3", 1e-3), ("mt3", 1e-1), ("mt3", 10.0), ("mt3", 1e3),
                    ("rosenbrock_line", 1e-3), ("rosenbrock_line", 1.0)]:
    for ftol, gtol in [(1e-3, 0.1), (0.1, 0.1), (1e-3, 0.9)]:
        cases.append(search(name, first, ftol, gtol, 0.1))
problems = [lbfgs("rosenbrock2", [-1.2, 1.0]), lbfgs("rosenbrock6", [-1.2, 1.0] * 3),
            lbfgs("quadratic8", [0.0] * 8)]
print(json.dumps({"dcsrch": cases, "lbfgs": problems, "quadratic": [x.tolist() for x in quadratic()]}))
