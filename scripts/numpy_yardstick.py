#!/usr/bin/env python3
"""The yardstick of `cellsweep bench`: a straightforward vectorized NumPy implementation of one
two-cell step of SPEC.md section 3 (np.roll stencils, one full-lattice array per term), on the
400 x 200 pair lattice with two fibers at L = 90 and the paper's defaults.

Start: two circles of radius R0 at (99.5, 99.5) and (299.5, 99.5), P = 1 inside the front half
of each (cell 1 towards +x, cell 2 towards -x), no noise. Prints one JSON object: seconds per
pair step (the fastest of five batches, and the mean), and the integrals after `check_steps` steps so that the Rust kernel can be compared
with this independent implementation.

Usage: numpy_yardstick.py [timed_steps] [check_steps]
"""
import json
import sys
import time

import numpy as np

NX, NY = 400, 200
ALPHA, BETA, SIGMA, L = 0.1, 14.0, 5.0, 90
D, R0, LAM, E0, AREF, G = 20 ** 0.5, 40.0, 1000.0, 2000.0, 1.0, 1.0
INV_GAMMA, ETA, A, TAU, DT, PHI_MIN = 50.0, 1.0, 200.0, 100.0, 0.002, 0.001

# Arrays are indexed [j, i] (y, x).
j, i = np.mgrid[0:NY, 0:NX].astype(float)
chi = np.zeros((NY, NX))
for row in (NY // 2 - L // 2 - 1, NY // 2 - L // 2, NY // 2 + L // 2 - 1, NY // 2 + L // 2):
    chi[row, :] = 1.0


def circle(cx):
    r = np.sqrt((i - cx) ** 2 + (j - 99.5) ** 2)
    return 0.5 + 0.5 * np.tanh((R0 - r) / (2 * D))


def lap(f):
    return np.roll(f, -1, 1) + np.roll(f, 1, 1) + np.roll(f, -1, 0) + np.roll(f, 1, 0) - 4 * f


def grad(f):
    return (np.roll(f, -1, 1) - np.roll(f, 1, 1)) / 2, (np.roll(f, -1, 0) - np.roll(f, 1, 0)) / 2


def step_cell(phi, p, other):
    a0 = np.pi * R0 ** 2
    s = np.sum(phi ** 2)
    ad = np.sum(phi ** 2 * (3 - 2 * phi) * chi)
    poly = phi ** 3 - 1.5 * phi ** 2 + 0.5 * phi
    mu = (ALPHA * (poly - D ** 2 / 2 * lap(phi))
          - 4 * LAM * phi / a0 * (1 - s / a0)
          - 6 * E0 * AREF * phi * (1 - phi) * chi / (AREF + ad) ** 2
          + 2 * G * phi * other ** 2
          - 2 * SIGMA * poly * other ** 2 * (1 - other) ** 2)
    gx, gy = grad(phi)
    gn = np.sqrt(gx ** 2 + gy ** 2)
    vgrad = (mu * gn ** 2 - A * p * phi ** 2 * (1 - phi) ** 2 * chi * gn) / ETA
    dphi = -(vgrad + mu * INV_GAMMA)
    p_new = (p + DT * (BETA * phi * dphi - p / TAU)) * (phi > PHI_MIN)
    return phi + DT * dphi, p_new


def start():
    phi1, phi2 = circle(99.5), circle(299.5)
    p1 = np.where((phi1 > 0.5) & (i >= 100), 1.0, 0.0)
    p2 = np.where((phi2 > 0.5) & (i <= 299), 1.0, 0.0)
    return phi1, p1, phi2, p2


def steps(fields, n):
    phi1, p1, phi2, p2 = fields
    for _ in range(n):
        (phi1, p1), (phi2, p2) = step_cell(phi1, p1, phi2), step_cell(phi2, p2, phi1)
    return phi1, p1, phi2, p2


def run(n):
    return steps(start(), n)


def main():
    timed = int(sys.argv[1]) if len(sys.argv) > 1 else 40
    check = int(sys.argv[2]) if len(sys.argv) > 2 else 10
    phi1, p1, phi2, p2 = run(check)
    # Warm up: the first steps of a process run slower (NumPy's temporaries come from fresh pages
    # until the allocator has settled), and a trajectory is hundreds of thousands of steps.
    fields = steps((phi1, p1, phi2, p2), 10)
    # Five batches, as `cellsweep bench` times the Rust steps: the fastest batch (the one the
    # neighbours on a shared machine disturbed least) and the mean over all of them.
    batches = 5
    per = max(1, timed // batches)
    times = []
    for _ in range(batches):
        t0 = time.perf_counter()
        fields = steps(fields, per)
        times.append((time.perf_counter() - t0) / per)
    print(json.dumps({
        "pair_step_s": min(times),
        "pair_step_mean_s": sum(times) / len(times),
        "timed_steps": per * batches,
        "check_steps": check,
        "sum_phi_1": float(phi1.sum()),
        "area_1": float((phi1 ** 2).sum()),
        "area_2": float((phi2 ** 2).sum()),
        "sum_p_1": float(p1.sum()),
        "numpy": np.__version__,
    }))


if __name__ == "__main__":
    main()
