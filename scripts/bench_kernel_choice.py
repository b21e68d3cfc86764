"""Benchmark: the native passive callback (a numba ``@cfunc``) against the same loads in C.

Issue 17 asked for the faster of two ways to put the hydrodynamics in native code: a numba
``@cfunc`` installed with ``mujoco.set_mjcb_passive`` (what ``mjtether.physics.native`` does), or a
MuJoCo engine plugin with the passive-force capability, written in C and built by the package.
A plugin's ``compute`` runs where ``mjcb_passive`` runs (in ``mj_passive``), so its cost is that
of a C callback doing the same work. This script writes that C callback for the tether's
Morison drag, buoyancy and weight-free loads (the kernel ``compiled.tether_loads`` with the
linear density and exponential current of ``bench_tether``; no seabed, no bending), builds it
with the system C compiler against the headers in MuJoCo's wheel, and times ``mj_step`` of the
``bench_tether`` model (N = 200, dt 5 ms) three ways, alternating rounds from the same state:

* ``us_per_step_bare``: no callback (MuJoCo alone, the cable in vacuum: timing only);
* ``us_per_step_numba``: mjtether's native callback;
* ``us_per_step_c``: the C callback (gcc -O2; the drum element's fairlead share as mjtether's).

A step's few microseconds of callback drown in the noise of a shared machine, so the callbacks
are also timed alone: ``us_per_call_numba`` and ``us_per_call_c``, each called through ctypes
(the same call overhead, under a microsecond) ``--calls`` times on the same state, in
alternating rounds (medians).

``agreement``: the largest difference of ``qfrc_passive`` between the two callbacks at the same
state, relative to its largest value (the same physics, to rounding). Without a C compiler the
C entries are null.

    python scripts/bench_kernel_choice.py [--json] [--steps 400] [--rounds 5] [--calls 20000]
"""

from __future__ import annotations

import argparse
import ctypes
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np

import mjtether as mt

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_tether  # noqa: E402  (the benchmark's model)

C_SOURCE = r"""
#include <math.h>
#include <mujoco/mujoco.h>

/* the tether: n elements from node 0 (flex vertex vertadr, first dof dof0), per element the
   rest length, diameter, C_dn, C_dt, area; linear density rho0 + drho depth; an exponential
   current u0 exp(-depth / decay) along (cos h, sin h) */
static int n, vertadr, dof0;
static const double *rest, *diam, *cdn, *cdt, *area;
static double rho0, drho, u0, decay, ch, sh, g, share;
static double *f;  /* (n + 1) x 3 work */

void set_params(int n_, int vertadr_, int dof0_, const double *rest_, const double *diam_, const double *cdn_,
                const double *cdt_, const double *area_, double rho0_, double drho_, double u0_, double decay_,
                double heading, double g_, double share_, double *work) {
  n = n_; vertadr = vertadr_; dof0 = dof0_; rest = rest_; diam = diam_; cdn = cdn_; cdt = cdt_; area = area_;
  rho0 = rho0_; drho = drho_; u0 = u0_; decay = decay_; ch = cos(heading); sh = sin(heading); g = g_; share = share_;
  f = work;
}

/* compiled._disk_wet: F, G, H of c */
static void disk_wet(double c, double *F, double *G, double *H) {
  double cc = c < -1 ? -1 : (c > 1 ? 1 : c), s = sqrt(1.0 - cc * cc), a = acos(cc), b = asin(cc);
  double cm = c > 1 ? c : 1.0;
  *F = (M_PI - a + cc * s) / M_PI;
  *G = (M_PI * cc - cc * a + s - s * s * s / 3.0) / M_PI + (c - 1.0 > 0 ? c - 1.0 : 0.0);
  *H = (M_PI * cc * cc / 2.0 - cc * cc * a / 2.0 - (b - cc * s) / 4.0 + (cc * (2.0 * cc * cc - 1.0) * s + b) / 8.0) / M_PI
       + (cm * cm - 1.0) / 2.0;
}

/* compiled._wet_fraction: the element's wet fraction and the centre of its wet part */
static void wet_fraction(double z0, double z1, double h, double *frac, double *centre) {
  if (z0 + h <= 0.0 && z1 + h <= 0.0) { *frac = 1.0; *centre = 0.5; return; }
  if (h > 1e-9) {
    if (z0 - h >= 0.0 && z1 - h >= 0.0) { *frac = 0.0; *centre = 0.5; return; }
    double c0 = -z0 / h, c1 = -z1 / h, dc = c1 - c0, F0, G0, H0, F1, G1, H1;
    if (fabs(dc) < 1e-4) {
      double cm = 0.5 * (c0 + c1), F, G, H;
      disk_wet(cm, &F, &G, &H);
      if (F <= 0.0) { *frac = 0.0; *centre = 0.5; return; }
      double slope = 2.0 * sqrt(1.0 - cm * cm > 0 ? 1.0 - cm * cm : 0.0) / M_PI, mid = 0.5 + dc * slope / (12.0 * F);
      *frac = F; *centre = mid < 0 ? 0 : (mid > 1 ? 1 : mid); return;
    }
    disk_wet(c0, &F0, &G0, &H0);
    disk_wet(c1, &F1, &G1, &H1);
    double G = G1 - G0;
    if (G == 0.0) { *frac = 0.0; *centre = 0.5; return; }
    double fr = G / dc, mid = ((H1 - H0) - c0 * G) / (dc * G);
    *frac = fr < 0 ? 0 : (fr > 1 ? 1 : fr); *centre = mid < 0 ? 0 : (mid > 1 ? 1 : mid); return;
  }
  double lo = z0 < z1 ? z0 : z1, hi = z0 < z1 ? z1 : z0, span = hi - lo, fr;
  if (span > 1e-12) { fr = -lo / span; fr = fr < 0 ? 0 : (fr > 1 ? 1 : fr); }
  else fr = lo <= 0.0 ? 1.0 : 0.0;
  *frac = fr; *centre = z0 <= z1 ? 0.5 * fr : 1.0 - 0.5 * fr;
}

void passive(const mjModel *m, mjData *d) {
  const double *x = d->flexvert_xpos + 3 * vertadr;
  const double *v = d->qvel + dof0;
  const double gauss = 0.5 / sqrt(3.0);
  for (int j = 0; j < 3 * (n + 1); j++) f[j] = 0.0;
  for (int i = 0; i < n; i++) {
    const double *a = x + 3 * i, *b = x + 3 * (i + 1);
    double t[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double len = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    double inv = 1.0 / (len > 1e-12 ? len : 1e-12);
    t[0] *= inv; t[1] *= inv; t[2] *= inv;
    double frac, centre, hh = 0.5 * diam[i] * sqrt(1.0 - t[2] * t[2] > 0 ? 1.0 - t[2] * t[2] : 0.0);
    wet_fraction(a[2], b[2], hh, &frac, &centre);
    double near[3] = {0, 0, 0}, far[3] = {0, 0, 0}, rho_mean = 0.0;
    for (int gp = 0; gp < 2; gp++) {  /* the drag at its two Gauss points, by the lever rule */
      double s = gp == 0 ? 0.5 - gauss : 0.5 + gauss;
      double zg = a[2] + s * (b[2] - a[2]), depth = zg < 0 ? -zg : 0;
      double rho = rho0 + drho * depth, speed = u0 * exp(-depth / decay);
      rho_mean += 0.5 * rho;
      double vr[3] = {speed * ch - ((1 - s) * v[3 * i] + s * v[3 * i + 3]),
                      speed * sh - ((1 - s) * v[3 * i + 1] + s * v[3 * i + 4]),
                      -((1 - s) * v[3 * i + 2] + s * v[3 * i + 5])};
      double vt = vr[0] * t[0] + vr[1] * t[1] + vr[2] * t[2];
      double vn[3] = {vr[0] - vt * t[0], vr[1] - vt * t[1], vr[2] - vt * t[2]};
      double vn_mag = sqrt(vn[0] * vn[0] + vn[1] * vn[1] + vn[2] * vn[2]);
      double q = (0.25 * rest[i] * diam[i]) * rho * frac;
      double kn = q * cdn[i] * vn_mag, kt = q * M_PI * cdt[i] * fabs(vt);
      for (int j = 0; j < 3; j++) {
        double dj = vn[j] * kn + vt * t[j] * kt;
        near[j] += (1 - s) * dj;
        far[j] += s * dj;
      }
    }
    double fb = (g * area[i] * rest[i]) * rho_mean * frac, lever = 1.0 - centre;
    if (share != 0.5 && i < 2) {  /* paying out: the drum element's load by the fairlead's share, the next half and half */
      double part = i == 0 ? share : 0.5;
      for (int j = 0; j < 3; j++) { double tot = near[j] + far[j]; near[j] = part * tot; far[j] = tot - near[j]; }
      if (i == 0) lever = share;
    }
    for (int j = 0; j < 3; j++) {
      f[3 * i + j] += near[j];
      f[3 * i + 3 + j] += far[j];
    }
    f[3 * i + 2] += lever * fb;
    f[3 * i + 5] += (1.0 - lever) * fb;
  }
  for (int j = 0; j < 3 * (n + 1); j++) d->qfrc_passive[dof0 + j] += f[j];
}
"""


def build_c(folder: Path) -> ctypes.CDLL | None:
    """The C callback, compiled; None without a C compiler."""
    cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        return None
    src, lib = folder / "passive.c", folder / "passive.so"
    src.write_text(C_SOURCE)
    include = Path(mujoco.__file__).parent / "include"
    subprocess.run([cc, "-O2", "-shared", "-fPIC", f"-I{include}", str(src), "-o", str(lib), "-lm"], check=True)
    return ctypes.CDLL(str(lib))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--steps", type=int, default=400)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--calls", type=int, default=20000)
    args = ap.parse_args(argv)
    sim, tether, water = bench_tether.make(200, 0.005)
    out = {"segments": 200, "timestep": 0.005, "compiler": None, "us_per_step_c": None, "us_per_call_c": None,
           "agreement": None}
    with sim, tempfile.TemporaryDirectory() as tmp:
        if not sim.native:
            raise SystemExit("bench_kernel_choice: the native callback is not available here")
        sim.step(200)  # (under way)
        m, d = sim.model, sim.data
        state = sim.save_state()
        t = sim.tether()
        lib = build_c(Path(tmp))
        c_callback = None
        if lib is not None:
            out["compiler"] = os.path.basename(os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc"))
            fast = t._fast
            keep = [np.ascontiguousarray(fast[k], dtype=float) for k in
                    ("diameter", "cd_normal", "cd_tangential", "area")] + [t._rest, np.zeros(3 * (t.n + 1))]
            dens, cur = water.density, water.current
            dbl = ctypes.POINTER(ctypes.c_double)
            p = [a.ctypes.data_as(dbl) for a in keep]
            lib.set_params.argtypes = [ctypes.c_int] * 3 + [dbl] * 5 + [ctypes.c_double] * 7 + [dbl]
            lib.set_params(t.n, t.vertadr, t._dof0, p[4], p[0], p[1], p[2], p[3], dens.rho_surface,
                           (dens.rho_ref - dens.rho_surface) / dens.depth_ref, cur.surface_speed, cur.decay_depth,
                           cur.heading, water.gravity, float(t._native_state[1]), p[5])
            c_callback = ctypes.cast(lib.passive, ctypes.c_void_p).value
            # the same forces at the same state
            sim.restore_state(state)
            mujoco.mj_forward(m, d)
            want = d.qfrc_passive.copy()
            mujoco.set_mjcb_passive(ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p)(c_callback))
            try:
                mujoco.mj_forward(m, d)
                got = d.qfrc_passive.copy()
            finally:
                mt.dispatch._install()
            out["agreement"] = float(f"{np.max(np.abs(got - want)) / np.max(np.abs(want)):.3g}")

        def timed(callback) -> float:
            sim.restore_state(state)
            if callback == "none":
                mujoco.set_mjcb_passive(None)
            elif callback == "c":
                mujoco.set_mjcb_passive(ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p)(c_callback))
            try:
                t0 = time.perf_counter()
                mujoco.mj_step(m, d, args.steps)
                return (time.perf_counter() - t0) / args.steps * 1e6
            finally:
                mt.dispatch._install()

        kinds = ["none", "numba"] + (["c"] if c_callback else [])
        times = {k: [] for k in kinds}
        for _ in range(args.rounds):
            for k in kinds:
                times[k].append(timed(k))
        # the callbacks alone, called through ctypes on the same state
        sim.restore_state(state)
        mujoco.mj_forward(m, d)
        signature = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p)
        calls = {"numba": signature(ctypes.cast(mt.native.callback(), ctypes.c_void_p).value)}
        if c_callback:
            calls["c"] = signature(c_callback)
        per_call = {k: [] for k in calls}
        for _ in range(args.rounds):
            for k, fn in calls.items():
                t0 = time.perf_counter()
                for _ in range(args.calls):
                    fn(m._address, d._address)
                per_call[k].append((time.perf_counter() - t0) / args.calls * 1e6)
    med = {k: float(np.median(v)) for k, v in times.items()}
    out.update(us_per_step_bare=round(med["none"], 1), us_per_step_numba=round(med["numba"], 1),
               us_per_call_numba=round(float(np.median(per_call["numba"])), 2))
    if "c" in med:
        out["us_per_step_c"] = round(med["c"], 1)
        out["us_per_call_c"] = round(float(np.median(per_call["c"])), 2)
    if args.json:
        print(json.dumps(out))
    else:
        for k, v in out.items():
            print(f"{k:22s} {v}")


if __name__ == "__main__":
    main()
