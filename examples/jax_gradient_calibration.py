"""
Gradient-based calibration with JAX
===================================

Recover the stiffness alpha and the shear viscosity eta_inf from plate tests, with exact
gradients through the library's own constitutive step compiled by JAX.

A synthetic data set is made with the numpy model: two vertical plate tests (intrude 3 cm,
hold 0.5 s, retract) at 1 and 4 cm/s in the paper's 25 % mud, with 1 % Gaussian noise. The
immediate resistance alpha does not depend on the speed and the shear viscosity eta_inf
scales with it, so two speeds separate them. Starting from alpha and eta_inf off by factors
of 0.5 and 3, scipy's L-BFGS-B minimizes the mean squared stress error, with the exact
gradient from ``jax.value_and_grad`` through :func:`mudrft.backends.jax.run` (a compiled
``lax.scan`` of the library's own constitutive step). Parameters are optimized in log space.

Run: ``python examples/jax_gradient_calibration.py [--out DIR]`` (a few seconds; needs
jax). With ``--out`` it also draws the fitted stress against the data
(``DIR/jax_gradient_calibration.png``).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import minimize

import mudrft
from mudrft.backends import jax as mjax

LC = 0.05  # plate characteristic length [m] (decision D1)


def synthetic_tests(truth: mudrft.MudParameters, *, noise: float = 0.01, seed: int = 0):
    """Two plate tests (time [s], gamma [-], noisy stress [Pa]) at 1 and 4 cm/s."""
    rng = np.random.default_rng(seed)
    tests = []
    for speed in (0.01, 0.04):
        traj = mudrft.plate_intrusion(depth=0.03, speed=speed, hold=0.5, dt=5e-3)
        clean = mudrft.plate_response(traj, truth, characteristic_length=LC).stress
        noisy = clean + noise * np.abs(clean).max() * rng.standard_normal(clean.shape)
        tests.append((traj.time, traj.depth / LC, noisy))
    return tests


def plot_fit(out: Path, tests, truth, fitted, start) -> Path:
    """The noisy data, the start and the fit: stress against time for both speeds."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6), constrained_layout=True)
    for ax, (t, g, s), speed in zip(axes, tests, (10, 40), strict=True):
        ax.plot(t, s / 1e3, ".", ms=2, color="0.6", label="synthetic data (1 % noise)")
        for params, label, style in (
            (start, "start", "C3--"),
            (fitted, "fit (L-BFGS-B + jax.grad)", "C0-"),
        ):
            stress = np.where(g > 0, np.asarray(mjax.run(mjax.to_jax(params), t, g).total), 0.0)
            ax.plot(t, stress / 1e3, style, lw=1.2, label=label)
        ax.set(
            xlabel="time [s]",
            ylabel="vertical stress [kPa]",
            title=f"plate test at {speed} mm/s, W = 25 %",
        )
        ax.legend(fontsize=8)
    path = out / "jax_gradient_calibration.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="Gradient-based calibration with the JAX backend.")
    ap.add_argument("--out", default=None, help="also draw the fit into this folder")
    ap.add_argument(
        "--quick", action="store_true", help="accepted for the docs build (already quick)"
    )
    args = ap.parse_args([] if argv is None else argv)  # None: the defaults
    jax = mjax.enable_x64()
    jnp = jax.numpy
    truth = mudrft.paper_parameters(0.25, "vertical")
    tests = synthetic_tests(truth)
    scale = max(float(np.abs(s).max()) for _, _, s in tests)
    start = {"alpha": 0.5 * truth.alpha, "eta_inf": 3.0 * truth.eta_inf}
    base = mjax.to_jax(truth.replace(**start))
    x0 = np.zeros(2)  # log(alpha / alpha_start), log(eta_inf / eta_inf_start)

    def loss(x):
        p = base._replace(alpha=base.alpha * jnp.exp(x[0]), eta_inf=base.eta_inf * jnp.exp(x[1]))
        err = 0.0
        for t, g, s in tests:
            # out of the mud (g = 0) the plate carries no stress, as in plate_response
            model = jnp.where(g > 0, mjax.run(p, t, g).total, 0.0)
            err = err + jnp.mean((model - s) ** 2)
        return err / scale**2

    value_and_grad = jax.jit(jax.value_and_grad(loss))
    calls = []

    def fun(x):
        v, g = value_and_grad(jnp.asarray(x))
        calls.append(float(v))
        print(
            f"  evaluation {len(calls):2d}: loss {float(v):.3e}, "
            f"alpha {start['alpha'] * np.exp(x[0]):8.0f} Pa, "
            f"eta_inf {start['eta_inf'] * np.exp(x[1]):8.0f} Pa s",
            file=sys.stderr,
        )
        return float(v), np.asarray(g, dtype=float)

    t0 = time.perf_counter()
    res = minimize(fun, x0, jac=True, method="L-BFGS-B", options={"maxiter": 100, "gtol": 1e-12})
    elapsed = time.perf_counter() - t0
    alpha = start["alpha"] * np.exp(res.x[0])
    eta_inf = start["eta_inf"] * np.exp(res.x[1])
    print(
        f"L-BFGS-B: {res.message} after {res.nit} iterations, {len(calls)} evaluations, "
        f"{elapsed:.2f} s (including compilation)"
    )
    print(
        f"alpha   : start {start['alpha']:9.0f}  fit {alpha:9.0f}  truth {truth.alpha:9.0f} Pa "
        f"({100 * (alpha / truth.alpha - 1):+.2f} %)"
    )
    print(
        f"eta_inf : start {start['eta_inf']:9.0f}  fit {eta_inf:9.0f}  "
        f"truth {truth.eta_inf:9.0f} Pa s ({100 * (eta_inf / truth.eta_inf - 1):+.2f} %)"
    )
    ok = abs(alpha / truth.alpha - 1) < 0.02 and abs(eta_inf / truth.eta_inf - 1) < 0.05
    print("recovered within 2 % (alpha) and 5 % (eta_inf)" if ok else "NOT recovered")
    if args.out:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        fitted = truth.replace(alpha=alpha, eta_inf=eta_inf)
        print("wrote", plot_fit(out, tests, truth, fitted, truth.replace(**start)).name)
    return 0 if ok else 1


if __name__ == "__main__":
    if main(sys.argv[1:]) != 0:
        sys.exit(1)
