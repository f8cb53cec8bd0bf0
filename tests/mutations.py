"""Mutation check: each planted physics error must make the fast test suite fail.

Usage::

    python tests/mutations.py            # all mutations, a table, exit 1 if one survives
    python tests/mutations.py --list     # the mutations and whether each patch applies
    python tests/mutations.py -k flash   # only mutations whose name contains "flash"

Every entry of :data:`MUTATIONS` is one tuple ``(name, file, old, new)``: the exact text
``old`` in ``file`` (relative to the repository root) is replaced by ``new``. An entry whose
``old`` text is not found exactly once is refused (the check stops before running anything),
so a mutation can never silently become a no-op after the code changes.

Each mutation is applied to a fresh copy of the repository in a temporary folder, and the
fast suite (the ``pytest`` defaults of ``pyproject.toml``: ``-m 'not slow'``) runs there with
``-x`` and ``PYTHONPATH`` pointing at the copy, so that the copy is imported and not the
installed package; this is verified before the first run. The copy leaves out virtual
environments, caches and build products. The test files are passed nearest first, so that a
caught mutation stops early: the tests that import the mutated module, then those that import
a module that imports it, and so on (:func:`test_files`, from the import graph of
``tests/import_graph.py``; a C source counts as the Python modules that name it), the
independent physics references (:data:`FIRST`) breaking ties; the set of tests is always the
whole fast suite. Mutations run in parallel (``-j``).
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from import_graph import PACKAGES, distances_to, import_graph, imports, module_name

ROOT = Path(__file__).resolve().parents[1]

#: (name, file, exact old text, new text). Add an entry as one tuple.
MUTATIONS: list[tuple[str, str, str, str]] = [
    # -- Persson engine (lookup/) ------------------------------------------------------------
    ("eq. (17) mu_visc prefactor halved", "lookup/friction.py",
     "contrib = 4.0 * sigma0[:, None] * rho", "contrib = 2.0 * sigma0[:, None] * rho"),
    ("eq. (18) P(q) argument as printed (erf(sqrt(G)/2))", "lookup/contact.py",
     "return erf(0.5 / np.sqrt(G))", "return erf(0.5 * np.sqrt(G))"),
    ("eq. (20) S(q) = gamma + (1 - gamma) P", "lookup/contact.py",
     "h = (S := gamma + (1.0 - gamma) * P * P) * P * Gf",
     "h = (S := gamma + (1.0 - gamma) * P) * P * Gf"),
    ("eq. (19) contact-area scaling: G prefactor 1/8 -> 1/4", "lookup/friction.py",
     "g = 0.125 * self.F * A_2 * s2", "g = 0.25 * self.F * A_2 * s2"),
    ("adhesive friction without the A/A0 factor", "lookup/friction.py",
     "mu_cont = sig_f * area / sigma0", "mu_cont = sig_f / sigma0"),
    ("loss modulus sign (E_I = +Im E)", "lookup/modulus.py",
     "return E.real, -E.imag", "return E.real, E.imag"),
    ("angular symmetry factor 4 -> 2 in the loss integral", "lookup/friction.py",
     'A_I = 4.0 * c * np.einsum("bqk,k->bq", EI',
     'A_I = 2.0 * c * np.einsum("bqk,k->bq", EI'),
    ("a_T direction reversed", "lookup/compound.py",
     "return self.shift.log10_aT(T) - self.shift.log10_aT(np.asarray(self.T_ref))",
     "return self.shift.log10_aT(np.asarray(self.T_ref)) - self.shift.log10_aT(T)"),
    ("WLF continuation slope sign", "lookup/shift.py",
     "slope = -self.C1 * self.C2 / (self.C2 + d_min) ** 2",
     "slope = self.C1 * self.C2 / (self.C2 + d_min) ** 2"),
    ("tabulated a_T: low-end extrapolation with the high-end slope", "lookup/shift.py",
     "s0 = (y[1] - y[0]) / (x[1] - x[0])", "s0 = (y[-1] - y[-2]) / (x[-1] - x[-2])"),
    ("Arrhenius eq. (22) sign", "lookup/shift.py",
     "(self.activation_energy / K_B) * (1.0 / T - 1.0 / self.T_ref)",
     "(self.activation_energy / K_B) * (1.0 / self.T_ref - 1.0 / T)"),
    ("eq. (6) Kraus eta_I peak doubled", "lookup/softening.py",
     "eta_I = 1.0 + 2.0 * (self.h - 1.0) * x / (1.0 + x * x)",
     "eta_I = 1.0 + 4.0 * (self.h - 1.0) * x / (1.0 + x * x)"),
    ("tabulated softening: eta_R and eta_I swapped", "lookup/softening.py",
     "return float(np.interp(ls, x, self.eta_R)), float(np.interp(ls, x, self.eta_I))",
     "return float(np.interp(ls, x, self.eta_I)), float(np.interp(ls, x, self.eta_R))"),
    ("flash contact time doubled (t_c = 2 D / v)", "lookup/friction.py",
     "t_c = self.D / key", "t_c = 2.0 * self.D / key"),
    ("flash: scale q felt at depth 1/q instead of 1/(2q)", "lookup/friction.py",
     "self.z_eval = np.concatenate([[0.0], 1.0 / (2.0 * self.q)])",
     "self.z_eval = np.concatenate([[0.0], 1.0 / self.q])"),
    ("q1 rule: rms slope of the self-affine plateau doubled", "lookup/roughness.py",
     "flat = 0.25 * (qa**4 - self.q0**4)", "flat = 0.5 * (qa**4 - self.q0**4)"),
    ("q1 rule: numerical rms slope without the 2 pi of sec. 4", "lookup/roughness.py",
     "f = 2.0 * np.pi * qq**4 * psd.C(qq)", "f = qq**4 * psd.C(qq)"),
    ("road heat partition: image strength with twice the road's effusivity",
     "lookup/friction.py", "self.R_image = (e_r - e_s) / (e_r + e_s)",
     "self.R_image = (e_r - e_s) / (e_r + 2.0 * e_s)"),
    ("eq. (21) shear law width c doubled", "lookup/adhesion.py",
     "return self.sigma_f0 * np.exp(-self.c * x * x)",
     "return self.sigma_f0 * np.exp(-2.0 * self.c * x * x)"),
    # -- calibration (lookup/calibration.py) ---------------------------------------------------
    ("calibration: cold shortcut without A/A0 (eq. 12)", "lookup/calibration.py",
     "mc = law.sigma_f(v, T) * area / p", "mc = law.sigma_f(v, T) / p"),
    ("calibration: covariance without the residual variance s^2", "lookup/calibration.py",
     "cov = s2 * (Vt.T * inv) @ Vt", "cov = (Vt.T * inv) @ Vt"),
    ("calibration: held-out points enter the fit", "lookup/calibration.py",
     "self.fitted = ~self.held_out", "self.fitted = np.ones_like(self.held_out)"),
    # -- FMU unit definitions (fmu_src/) ------------------------------------------------------
    ("FMU degC display offset sign", "fmu_src/runtime/interface.py",
     '"K": (("degC", 1.0, -273.15),),', '"K": (("degC", 1.0, 273.15),),'),
    ("FMU rad/s base-unit exponent", "tirefric/units.py",
     '"angular_frequency": ("rad/s", {"rad": 1, "s": -1}),',
     '"angular_frequency": ("rad/s", {"rad": 1, "s": 1}),'),
    ("FMU N.m base-unit exponent", "tirefric/units.py",
     '"moment": ("N.m", {"kg": 1, "m": 2, "s": -2}),',
     '"moment": ("N.m", {"kg": 1, "m": 1, "s": -2}),'),
    ("FMU state error outside the TirefricError hierarchy", "fmu_src/runtime/state.py",
     "class StateFormatError(TirefricError, ValueError):", "class StateFormatError(ValueError):"),
    # -- tire and braking (tire_brush/) -------------------------------------------------------
    ("slip defined on the rolling speed (omega R_e) instead of vx", "tire_brush/slip.py",
     "kappa = (omega * R_e - vx) / ref",
     "kappa = (omega * R_e - vx) / max(abs(omega * R_e), v_floor)"),
    ("OCP objective: distance maximised", "tire_brush/braking/ocp.py",
     "f_obj = Z[0, N] + rate_penalty", "f_obj = -Z[0, N] + rate_penalty"),
    ("thermal bound: sliding power without the slip (kappa = -1 heat at every slip)",
     "tire_brush/braking/thermal_dp.py",
     "heat = th.heat_fraction * mu[i] * car.Fz * (-kappa)[None, :] * vm[i]",
     "heat = th.heat_fraction * mu[i] * car.Fz * np.ones_like(kappa)[None, :] * vm[i]"),
    ("thermal bound: ramp phase credits no distance", "tire_brush/braking/thermal_dp.py",
     "            if x[k] + rest > best:\n                best, t_best = x[k] + rest,",
     "            if rest > best:\n                best, t_best = rest,"),
    # -- the real-time fidelity (tire_brush/csrc/tirert.c) ----------------------------------
    ("real-time: the belt's yaw turns the patch's slip the wrong way",
     "tire_brush/csrc/tirert.c", "h * ((Vsy - V_r * s->psi) - s->Vp[1])",
     "h * ((Vsy + V_r * s->psi) - s->Vp[1])"),
    ("real-time: the tread's heat from the friction power halved", "tire_brush/csrc/tirert.c",
     "double Q = P * h;", "double Q = 0.5 * P * h;"),
    ("real-time: no transit lag of the adhesion zone", "tire_brush/csrc/tirert.c",
     "double tau = ((2.0 / 3.0) * a) * (1.0 - frac) / vr;", "double tau = 0.0;"),
    ("real-time: the water depth not read (the dry layer on water)",
     "tire_brush/csrc/tirert.c", "d_water, o);", "0.0, o);"),
    # -- tire core (tire_brush/csrc/tirecore.c, what the models and the FMU run) -------------
    ("tire core: eq. (28) with s0 halved", "tire_brush/csrc/tirecore.c",
     "    S.inv_s0 = t->inv_s0;\n", "    S.inv_s0 = 2.0 * t->inv_s0;\n"),
    ("tire core: element stick test reversed", "tire_brush/csrc/tirecore.c",
     "if (S.G <= mu0 * S.pf) {", "if (S.G >= mu0 * S.pf) {"),
    ("tire core: tread temperature heat source halved", "tire_brush/csrc/tirecore.c",
     "(p->heat_fraction * Q + h", "(0.5 * p->heat_fraction * Q + h"),
    ("tire core: elements enter at rest instead of with the belt",
     "tire_brush/csrc/tirecore.c",
     "            e[2] = Vbx;\n            e[3] = Vby + x_in * c.wpsi;\n",
     "            e[2] = 0.0;\n            e[3] = 0.0;\n"),
    ("tire core: belt sees no stiffness from sliding elements", "tire_brush/csrc/tirecore.c",
     "        jx += ex;\n        jy += ey;\n",
     "        jx += 0.0 * ex;\n        jy += 0.0 * ey;\n"),
    ("tire core: a sliding element's stiffness from one implicit Euler step",
     "tire_brush/csrc/tirecore.c",
     "        double ex = element_stiffness(p->k_x, p->d_x, p->mass, cs, h);\n"
     "        double ey = element_stiffness(p->k_y, p->d_y, p->mass, cs, h);\n",
     "        double ex = kdx * (p->mass / h + cs) / (p->mass / h + kdx + cs);\n"
     "        double ey = kdy * (p->mass / h + cs) / (p->mass / h + kdy + cs);\n"),
    ("tire core: the outer step ignores the belt's lateral-yaw loop",
     "tire_brush/csrc/tirecore.c",
     "    if (p->rigid || !(a > 0.0 && b > 0.0) || !(belt_gain(p, V_r, a, b, h) > BELT_GAIN_MAX))",
     "    if (1)"),
    ("tire core: the work budget is never spent", "tire_brush/csrc/tirecore.c",
     "        if (c->w && !(c->w->left > 0.0)) {", "        if (0) {"),
    ("tire core: the budget's fallback drops the rest of the step", "tire_brush/csrc/tirecore.c",
     "            stage(c, rest, pe, vbe, ux, uy, wx, wy, s, th, norm2(wx, wy), &o2);",
     "            stage(c, 1e-300, pe, vbe, ux, uy, wx, wy, s, th, norm2(wx, wy), &o2);"),
    ("tire core: triangular instead of parabolic pressure ends", "tire_brush/csrc/tirecore.c",
     "    double w = 1.0 - t * t;\n    return w > 0.0 ? w : 0.0;",
     "    double w = 1.0 - t;\n    return w > 0.0 ? w : 0.0;"),
    ("tire core: the belt's twist turns the tread the wrong way", "tire_brush/csrc/tirecore.c",
     "        Vby = (Vsy + uy) - V_r * tire->psi;", "        Vby = (Vsy + uy) + V_r * tire->psi;"),
    ("tire core: elements leaving the patch during a step are dropped",
     "tire_brush/csrc/tirecore.c",
     "        if (!(x < a && x > -a)) {\n            if (e[6] == 0.0) continue;",
     "        if (!(x < a && x > -a)) {\n            if (1) continue;"),
    ("tire core: eq. (28) weight frozen at the start of a stage (not along the slip)",
     "tire_brush/csrc/tirecore.c",
     "    double E = S->inv_s0 > 0.0 ? cold_weight((S->Zs + S->Hs * V) * S->inv_s0) : 1.0;\n"
     "    double dm = mc - mh;",
     "    double E = S->inv_s0 > 0.0 ? cold_weight(S->Zs * S->inv_s0) : 1.0;\n"
     "    double dm = mc - mh;"),
    ("tire core: road force from the end-of-step friction only", "tire_brush/csrc/tirecore.c",
     "Jx += H * ((1.0 - GAMMA) * o1.fx + GAMMA * o2.fx);", "Jx += H * o2.fx;"),
    ("tire core: camber spins the base the wrong way", "tire_brush/csrc/tirecore.c",
     "double wc = -(1.0 - p->camber_reduction) * omega * sin(gam);",
     "double wc = (1.0 - p->camber_reduction) * omega * sin(gam);"),
    ("tire core: overturning moment of the opposite shift", "tire_brush/csrc/tirecore.c",
     "o[10] = p->rigid ? 0.0 : -tire->delta[1] * Fz;",
     "o[10] = p->rigid ? 0.0 : tire->delta[1] * Fz;"),
    ("tire core: rolling resistance drives the wheel", "tire_brush/csrc/tirecore.c",
     "o[11] = (V_r > 0.0 ? 1.0 : V_r < 0.0 ? -1.0 : 0.0)",
     "o[11] = (V_r > 0.0 ? -1.0 : V_r < 0.0 ? 1.0 : 0.0)"),
    ("tire core: rolling loss does not heat the tread", "tire_brush/csrc/tirecore.c",
     "(p->heat_fraction * Q + h * q_roll +", "(p->heat_fraction * Q + 0.0 * q_roll +"),
    ("tire core: wet dry-share weights swapped", "tire_brush/csrc/tirecore.c",
     "v[0] = (1.0 - ws) * c0 + ws * c1;", "v[0] = ws * c0 + (1.0 - ws) * c1;"),
    ("asperity squeeze-out: Stefan time without the factor 3/4 (threshold x 4/3)",
     "lookup/wet/squeeze.py",
     "return 3.0 * np.asarray(eta, float) * r * np.abs(np.asarray(v, float)) / (8.0 * h_c * h_c)",
     "return 4.0 * np.asarray(eta, float) * r * np.abs(np.asarray(v, float)) / (8.0 * h_c * h_c)"),
    ("tire core: drainage time at the rolling speed, not the entrainment speed",
     "tire_brush/csrc/tirecore.c",
     "double U = 0.5 * (fabs(vx) + fabs(V_r));", "double U = fabs(V_r);"),
    ("wet tire: drainage time halved", "tire_brush/wet_friction.py",
     "    return t_fp * (D / (2.0 * R)) ** 2", "    return 0.5 * t_fp * (D / (2.0 * R)) ** 2"),
    ("rolling resistance: ring tail decays over the patch half-length, not the matched slope",
     "tire_brush/rolling_resistance.py",
     "return w_a, (w_a * R0 / a if a > 0 else 0.0)", "return w_a, (a if a > 0 else 0.0)"),
    ("rolling resistance: the structure's share held at chi (stiffening with the inflation)",
     "tire_brush/rolling_resistance.py",
     "return rr.deflection_energy_share * params.patch.C_z / params.patch.vertical_stiffness",
     "return rr.deflection_energy_share"),
    ("rolling resistance: the tread's pressure imposed (series factor dropped)",
     "tire_brush/rolling_resistance.py",
     "return np.abs(c_t_ref + c_b) ** 2 / np.abs(c_t + c_b) ** 2",
     "return 1.0 + 0.0 * np.abs(c_t + c_b)"),
    ("rolling resistance: the belt's compliance without its hoop tension",
     "tire_brush/rolling_resistance.py",
     "return b / (rr.belt_bending_stiffness * q**4 + tension * q * q + k)",
     "return b / (rr.belt_bending_stiffness * q**4 + k)"),
    ("tire core: hydroplaning lift linear in speed (Horne: quadratic)",
     "tire_brush/csrc/tirecore.c",
     "double rv = (vx / Vp) * (vx / Vp);", "double rv = fabs(vx / Vp);"),
    ("partial lift linear in speed (Horne & Dreher's dynamic pressure: quadratic)",
     "tire_brush/hydroplaning.py", "np.minimum(r * r, 1.0), 0.0)", "np.minimum(r, 1.0), 0.0)"),
    ("Gallaway's texture term with the exponent's sign flipped",
     "tire_brush/hydroplaning.py", "math.pow(txd / _IN, 0.14)", "math.pow(txd / _IN, -0.14)"),
    ("partial lift on the whole water depth, not the film above the texture",
     "tire_brush/hydroplaning.py", "film = np.maximum(d - texture_depth, 0.0)", "film = d"),
    # -- axis conventions and the Magic Formula fit (tire_brush/axes.py, mf_fit.py) ----------
    ("adapted SAE Fy taken as the ISO Fy", "tire_brush/axes.py",
     'vy=-1, gamma=1, kappa=1, Fx=1, Fy=-1, Fz=1, Mx=1, My=-1,',
     'vy=-1, gamma=1, kappa=1, Fx=1, Fy=1, Fz=1, Mx=1, My=-1,'),
    ("MF fit on the brush's own (adapted SAE) signs, not ISO-W", "tire_brush/mf_fit.py",
     'BRUSH_AXES, "iso-w")\n    return FitPoints(',
     'BRUSH_AXES, "adapted-sae")\n    return FitPoints('),
    ("MF trail without the load factor Fz/Fz0 (eq. 4.E42)", "tire_brush/magic_formula.py",
     'Dt = Fz * (R0 / p["FNOMIN"])', 'Dt = (R0 / p["FNOMIN"]) * p["FNOMIN"]'),
]

#: Test files run first (independent references; cheap); the rest follow in name order.
FIRST = ["test_physics_reference.py", "test_closed_form_pins.py", "test_fmu_units.py",
         "test_slip_kinematics.py", "test_errors.py", "test_persson_engine.py"]

IGNORE = shutil.ignore_patterns(".git", ".venv*", "venv", "*.egg-info", "__pycache__",
                                ".pytest_cache", ".ruff_cache", ".core-cache", "build", "dist",
                                "_tirecore*", "demo_out", "out")


def check_patches(mutations: list[tuple[str, str, str, str]]) -> list[str]:
    """Problems with the list: an ``old`` text not found exactly once, a no-op, a duplicate."""
    problems = []
    names = [m[0] for m in mutations]
    for name, rel, old, new in mutations:
        path = ROOT / rel
        if names.count(name) > 1:
            problems.append(f"{name}: duplicate name")
        if old == new:
            problems.append(f"{name}: old and new text are equal")
        if not path.is_file():
            problems.append(f"{name}: no file {rel}")
            continue
        n = path.read_text().count(old)
        if n != 1:
            problems.append(f"{name}: old text found {n} times in {rel} (must be exactly 1)")
    return problems


def copy_repo(dest: Path) -> Path:
    """A copy of the working tree, importable as the package (``models`` also as
    ``tirefric_models``, the name it is installed under)."""
    shutil.copytree(ROOT, dest, ignore=IGNORE, symlinks=True)
    (dest / "tirefric_models").symlink_to("models", target_is_directory=True)
    return dest


def environment(copy: Path) -> dict[str, str]:
    # the copy has no built tire core: it is compiled from the copy's (mutated) C sources
    # into a cache inside the copy
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONDONTWRITEBYTECODE="1",
               TIREFRIC_CACHE=str(copy / ".core-cache"))
    env.pop("TIREFRIC_CORE", None)
    env["PYTHONPATH"] = os.pathsep.join([str(copy), str(copy / "tests")]
                                        + ([env["PYTHONPATH"]] if env.get("PYTHONPATH")
                                           else []))
    return env


def verify_imports(copy: Path) -> None:
    """Fail unless the copy's packages are the ones imported with :func:`environment`."""
    code = ("import tirefric, lookup, tire_brush, fmu_src, tirefric_models, sys\n"
            "for m in (tirefric, lookup, tire_brush, fmu_src, tirefric_models):\n"
            "    print(m.__file__)\n")
    r = subprocess.run([sys.executable, "-c", code], cwd=copy, env=environment(copy),
                       capture_output=True, text=True, check=True)
    files = r.stdout.split()
    outside = [f for f in files if not Path(f).resolve().is_relative_to(copy.resolve())]
    if len(files) != 5 or outside:
        raise SystemExit(f"the temporary copy is not the imported package: {files}")


#: The Python modules of each C source: its loader, and for the tire core its operation-for-
#: operation Python mirror (the tests pinning the two import the mirror).
C_OWNERS = {"tire_brush/csrc/tirecore.c": ("tire_brush.element", "tire_brush.ccore"),
            "tire_brush/csrc/tirecore.h": ("tire_brush.element", "tire_brush.ccore"),
            **{f"fmu_src/runtime/native/{name}": ("fmu_src.make.native_build",)
               for name in ("fmu_wrapper.c", "tfn_model.c", "tfn_files.c", "tfn_model.h")}}


def modules_of(rel: str, root: Path = ROOT) -> list[str]:
    """The project modules a mutated file belongs to: a Python module itself; a C source its
    loader (:data:`C_OWNERS`), or else the modules whose source names it."""
    path = root / rel
    if path.suffix == ".py":
        return [module_name(path, root)]
    if rel in C_OWNERS:
        return list(C_OWNERS[rel])
    return sorted(module_name(p, root) for pkg in PACKAGES for p in (root / pkg).rglob("*.py")
                  if path.name in p.read_text(encoding="utf-8"))


def test_files(copy: Path, rel: str = "") -> list[str]:
    """All fast-suite test files, nearest the mutated file ``rel`` first (module docstring)."""
    names = sorted(p.name for p in (copy / "tests").glob("test_*.py"))
    far = 10**6
    dist: dict[str, int] = {}
    if rel:
        graph = import_graph(copy)
        for m in modules_of(rel, copy):
            for k, d in distances_to(m, graph).items():
                dist[k] = min(dist.get(k, far), d)

    def rank(name: str) -> tuple[int, int, str]:
        deps = imports(copy / "tests" / name, copy)
        near = min((dist[d] for d in deps if d in dist), default=far)
        return near, FIRST.index(name) if name in FIRST else len(FIRST), name

    return [f"tests/{f}" for f in sorted(names, key=rank)]


def run_one(mutation: tuple[str, str, str, str], tmp: Path) -> tuple[str, bool, str, float]:
    """Apply one mutation to a fresh copy and run the fast suite; (name, caught, by, s)."""
    name, rel, old, new = mutation
    t0 = time.perf_counter()
    copy = copy_repo(tmp / re.sub(r"\W+", "_", name)[:60])
    path = copy / rel
    path.write_text(path.read_text().replace(old, new, 1))
    cmd = [sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider",
           "--no-header", "-rf", *test_files(copy, rel)]
    r = subprocess.run(cmd, cwd=copy, env=environment(copy), capture_output=True, text=True)
    failed = re.findall(r"^(?:FAILED|ERROR) (\S+)", r.stdout, re.M)
    caught = r.returncode != 0
    if failed:
        by = failed[0].removeprefix("tests/")
    else:
        by = f"pytest exit {r.returncode}" if caught else "-"
    shutil.rmtree(copy, ignore_errors=True)
    return name, caught, by, time.perf_counter() - t0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-k", default="", help="only mutations whose name contains this text")
    ap.add_argument("-j", type=int, default=os.cpu_count() or 1, help="parallel runs")
    ap.add_argument("--list", action="store_true", help="list the mutations and stop")
    args = ap.parse_args(argv)
    chosen = [m for m in MUTATIONS if args.k.lower() in m[0].lower()]
    problems = check_patches(chosen)
    if args.list:
        for name, rel, _, _ in chosen:
            print(f"{name:64s} {rel}")
    if problems:
        print("refusing to run:\n  " + "\n  ".join(problems), file=sys.stderr)
        return 2
    if args.list or not chosen:
        return 0
    with tempfile.TemporaryDirectory(prefix="tirefric-mut-") as d:
        tmp = Path(d)
        verify_imports(copy_repo(tmp / "import_check"))
        with ThreadPoolExecutor(max(args.j, 1)) as pool:
            rows = list(pool.map(lambda m: run_one(m, tmp), chosen))
    w = max(len(r[0]) for r in rows)
    print(f"{'mutation':{w}s}  caught  {'by (first failing test)':60s}  time")
    for name, caught, by, t in rows:
        print(f"{name:{w}s}  {'yes' if caught else 'NO':6s}  {by:60s}  {t:5.0f} s")
    survived = [r[0] for r in rows if not r[1]]
    print(f"{len(rows) - len(survived)}/{len(rows)} caught"
          + (f"; SURVIVED: {', '.join(survived)}" if survived else ""))
    return 1 if survived else 0


if __name__ == "__main__":
    sys.exit(main())
