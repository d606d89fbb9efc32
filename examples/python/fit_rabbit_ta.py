# %% [markdown]
# # Passive Hill parameters from the rabbit tibialis anterior
#
# Fits the passive parameters of the Hill muscle (matrix `c` [Pa], `b` [1] and parallel
# element `A` [1]) to the passive tension of the rabbit tibialis anterior measured by
# Winters, Takahashi, Lieber & Ward (2011, J Biomech 44:109, Fig. 3C; digitized by
# M. Millard, MIT licence), with `scipy.optimize.least_squares` calling a musclefem
# material point in uniaxial stress along its fiber.
#
#     python examples/python/fit_rabbit_ta.py OUT_DIR [--data CSV] [--quick]
#
# writes `OUT_DIR/fit_rabbit_ta.png` (data, start and fitted curves) and
# `OUT_DIR/fit_rabbit_ta.json` (the fitted values and the residual). The data are read
# from `../shared/data/rabbit_ta/` beside the checkout (see that folder's README); they
# are not part of this repository. Needs musclefem, NumPy, SciPy and matplotlib
# (`scripts/setup-python.sh` installs them into `target/python-venv`).

# %%
import argparse
import csv
import json
import pathlib
import sys
import time

import matplotlib

matplotlib.use("Agg")  # files only: no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.optimize import least_squares  # noqa: E402

import musclefem  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = (
    ROOT.parent / "shared" / "data" / "rabbit_ta"
    / "rabbit_TA_TMWinters2011_TA_fpeN_mjhmilla_digitized.csv"
)

parser = argparse.ArgumentParser(description=__doc__)
parser.add_argument("out", type=pathlib.Path, help="output directory (PNG and JSON)")
parser.add_argument("--data", type=pathlib.Path, default=DATA, help="the passive curve (CSV: x, ta)")
parser.add_argument(
    "--quick", action="store_true", help="coarser driver step (dt 0.05 s instead of 0.01 s)"
)
args = parser.parse_args()
args.out.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# ## The data
#
# `x` is the fiber length change in % of the optimal fiber length, `ta` the passive
# tension in % of the maximum isometric tension P0. The model's fiber stretch is relative
# to the rest length, at which the optimal stretch is `lambda_opt` (1.05 in Table 1):
# stretch = lambda_opt (1 + x / 100). Tension in % of P0 is compared with the engineering
# stress (force over reference area) in % of `sigma0` (700 kPa). Only the points from the
# optimal length on (x >= 0) are fitted: below it the passive tension is nil in the data
# and the parallel element is slack.

# %%
if not args.data.is_file():
    sys.exit(f"{args.data}: not found (the reference data live in ../shared/data beside the checkout)")
with open(args.data) as table:
    rows = [(float(r["x"]), float(r["ta"])) for r in csv.DictReader(table)]
strain_percent = np.array([r[0] for r in rows])
tension_percent = np.array([r[1] for r in rows])
fitted_points = strain_percent >= 0.0
print(f"{len(rows)} points, {fitted_points.sum()} from the optimal length on")

hill = {m["name"]: m for m in musclefem.materials()}["hill"]
defaults = {p["name"]: p["default"] for p in hill["parameters"]}
SIGMA0 = defaults["sigma0"]
LAMBDA_OPT = defaults["lambda_opt"]
stretch_data = LAMBDA_OPT * (1.0 + strain_percent[fitted_points] / 100.0)
measured = tension_percent[fitted_points]

# %% [markdown]
# ## The model
#
# A passive (n2 = 0) Hill material point pulled along its fiber from stretch 1 to beyond
# the largest measured stretch in 1 s, its engineering stress read off at the measured
# stretches (linearly between the driver's steps).

# %%
NAMES = ["c", "b", "A"]
DT = 0.05 if args.quick else 0.01
top = 1.01 * stretch_data.max()
runs = 0


def model(values, stretches):
    """Engineering stress in % of sigma0 at `stretches` for parameters `values`."""
    global runs
    runs += 1
    point = musclefem.MaterialPoint("hill", n2=0.0, **dict(zip(NAMES, values)))
    curve = point.uniaxial([0.0, 1.0], [1.0, top], dt=DT)
    stress = np.interp(stretches, curve["stretch"], curve["engineering_stress_pa"])
    return 100.0 * stress / SIGMA0


def residuals(values):
    return model(values, stretch_data) - measured


# %% [markdown]
# ## The fit
#
# Bounded (c, A >= 0, b > 0) trust-region least squares from Table 1's values, with
# forward differences; parameters scaled by their start values.

# %%
start = np.array([defaults[n] for n in NAMES])
started = time.perf_counter()
solution = least_squares(
    residuals,
    start,
    bounds=([0.0, 1e-3, 0.0], [np.inf, 100.0, 100.0]),
    x_scale=start,
    diff_step=1e-6,
)
elapsed = time.perf_counter() - started
fitted = dict(zip(NAMES, solution.x))
rms = float(np.sqrt(np.mean(solution.fun**2)))
r_squared = float(1.0 - np.sum(solution.fun**2) / np.sum((measured - measured.mean()) ** 2))
start_rms = float(np.sqrt(np.mean(residuals(start) ** 2)))
print(", ".join(f"{n} = {v:.6g}" for n, v in fitted.items()))
print(f"RMS residual {rms:.3f} % P0 (start {start_rms:.3f}), R^2 = {r_squared:.4f}, "
      f"{runs} material-point runs in {elapsed:.2f} s ({solution.message})")

# %% [markdown]
# ## The plot

# %%
curve_strain = np.linspace(0.0, strain_percent.max(), 200)
curve_stretch = LAMBDA_OPT * (1.0 + curve_strain / 100.0)
figure, axes = plt.subplots(figsize=(7, 4.5))
axes.plot(strain_percent, tension_percent, "o", ms=3, color="0.5", label="Winters 2011 (rabbit TA)")
axes.plot(curve_strain, model(start, curve_stretch), "--", label="Table 1 (leaves the chart)")
label = ", ".join(f"{n} = {v:.3g}" for n, v in fitted.items())
axes.plot(curve_strain, model(solution.x, curve_stretch), "-", label=f"fitted: {label}")
axes.set_ylim(-5.0, 1.3 * tension_percent.max())
axes.set_xlabel("fiber length change [% of optimal length]")
axes.set_ylabel("passive tension [% of P0]")
axes.set_title("Passive Hill muscle (material point) fitted to the rabbit TA")
axes.legend(loc="upper left")
figure.tight_layout()
figure.savefig(args.out / "fit_rabbit_ta.png", dpi=120)

# %%
summary = {
    "parameters": fitted,
    "start": dict(zip(NAMES, start.tolist())),
    "rms_percent_p0": rms,
    "start_rms_percent_p0": start_rms,
    "r_squared": r_squared,
    "points": int(fitted_points.sum()),
    "runs": runs,
    "dt_s": DT,
    "status": int(solution.status),
}
(args.out / "fit_rabbit_ta.json").write_text(json.dumps(summary, indent=2) + "\n")
print(f"wrote {args.out / 'fit_rabbit_ta.png'} and {args.out / 'fit_rabbit_ta.json'}")
