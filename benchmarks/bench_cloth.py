"""Cloth throughput: steps per second for a hanging n×n sheet, with every ratio measured in the same run.

The sheet: spacing 1.85 m, 0.1 kg per point, springs 10 N/m to the 8 neighbours, top row pinned,
gravity, ATRITO 0.5, h = 1 ms (the curtain's numbers). Measured in one process:

* ``run``: ``eigengait cloth run SHEET.PAR --no-render`` (forward Euler, as FLEX3D), in-process,
  wall time of the whole command including the .OBT/.obj frames it writes, after a warm-up run that
  compiles the kernels; with the default 10 % strain limit and with ``--strain-limit 0``.
* ``implicit``: the same command with ``--integrator implicit --time-step 1/60`` (one step per 60 Hz
  frame).
* ``numpy``: a plain vectorized NumPy loop over the same sheet's springs (forces, friction, forward
  Euler).
* ``mujoco``: MuJoCo's own flex cloth (``<flexcomp type="grid" dim="2">``), same grid and pins,
  contacts off.
* ``warp``: NVIDIA Warp's CPU backend (``pip install eigengait[bench]``) running the same springs
  and forward Euler as two kernels per step (float32, as Warp's own cloth example).

Rates are steps per second of the process's CPU time (``time.process_time``; every contender runs on
one thread), best of ``--rounds`` interleaved rounds, so that other jobs on a shared machine disturb
the ratios as little as possible. On an idle machine CPU time and wall time agree.

Run: python benchmarks/bench_cloth.py [--sizes 20 100] [--seconds 2] [--rounds 3]
"""  # noqa: E501

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from eigengait.cloth.model import surface_model
from eigengait.cloth.par import SurfaceSpec

try:
    import warp as wp
except ImportError:
    wp = None

SPACING, MASS, K, FRICTION, H = 1.85, 0.1, 10.0, 0.5, 0.001


def sheet_script(n: int, duration: float, time_step: float = H) -> str:
    """A .PAR script of the hanging n×n sheet, one frame per second."""
    fixed = "\n".join(f"    0 {j}" for j in range(n))
    return (
        f"DURACAO = {duration}\nQUADROS_SEG = 1\nDELTA_t = {time_step}\nATRITO = {FRICTION}\n"
        f"NUM_SUPERFICIES = 1\nSUPERFICIE sheet\n  MALHA ({n} {n})\n  DENSIDADE = {SPACING}\n"
        f"  POSIC_NO_SRU (0 40 0)\n  VETOR_NORMAL (0 0 1)\n  MASSA = {MASS}\n  CONST_ELASTICIDADE "
        f"= ({K} {K} {K})\n"
        f"  RESTRICOES\n    PONTOS_FIXOS = {n}\n{fixed}\n  FIM_RESTRICOES\nFIM_SUPERFICIE\n"
    )


def run_rate(n: int, seconds: float, *options: str, time_step: float = H) -> float:
    """Steps per second of ``cloth run`` on the sheet (in-process, no rendering)."""
    from typer.testing import CliRunner

    from eigengait.cli import build_app

    app = build_app()
    with tempfile.TemporaryDirectory() as folder:
        script = Path(folder) / "sheet.PAR"
        args = [
            "cloth",
            "run",
            str(script),
            "-o",
            str(Path(folder) / "out"),
            "--no-render",
            "--force",
            *options,
        ]
        if time_step != H:
            args += ["--time-step", repr(time_step)]
        script.write_text(sheet_script(n, 1.0, time_step))
        CliRunner().invoke(app, args)  # warm-up: compiles (or loads) the kernels
        script.write_text(sheet_script(n, seconds, time_step))
        start = time.process_time()
        result = CliRunner().invoke(app, args)
        elapsed = time.process_time() - start
    if result.exit_code != 0:
        raise RuntimeError(result.output)
    return round(seconds / time_step) / elapsed


def hanging(n: int):
    spec = SurfaceSpec(
        "sheet",
        n,
        n,
        SPACING,
        np.zeros(3),
        np.array([0.0, -1.0, 0.0]),
        MASS,
        (K,) * 3,
        (0.0,) * 3,
        fixed=[(0, j) for j in range(n)],
    )
    return surface_model([spec], gravity=(0, 0, -9.81), friction=FRICTION)


def numpy_rate(n: int, budget: float = 1.0) -> float:
    """A plain NumPy loop over the sheet's springs: forces, scatter by bincount, friction, forward
    Euler."""
    model = hanging(n)
    i, j, rest = model.springs[:, 0], model.springs[:, 1], model.spring_rest
    x, v = model.rest_positions.copy(), np.zeros((model.size, 3))
    free = model.free[:, None]
    gravity = MASS * np.array([0.0, 0.0, -9.81])
    steps, start = 0, time.process_time()
    while time.process_time() - start < budget:
        d = x[j] - x[i]
        length = np.linalg.norm(d, axis=1)
        f = (K * (length - rest) / length)[:, None] * d
        force = (
            np.stack(
                [
                    np.bincount(i, f[:, c], model.size) - np.bincount(j, f[:, c], model.size)
                    for c in range(3)
                ],
                axis=1,
            )
            + gravity
        )
        speed = np.linalg.norm(v, axis=1)
        drag = np.minimum(FRICTION * np.linalg.norm(force, axis=1), MASS * speed / H) / np.maximum(
            speed, 1e-300
        )
        x = x + H * v * free
        v = v + H * (force - drag[:, None] * v) / MASS * free
        steps += 1
    return steps / (time.process_time() - start)


def mujoco_rate(n: int, budget: float = 1.0) -> float | None:
    """MuJoCo flex grid of the same size, top row pinned, edge springs; None if the scene cannot be
    built."""
    import mujoco

    pins = " ".join(str(i * n + (n - 1)) for i in range(n))
    xml = f"""<mujoco><option timestep="{H}" solver="CG" iterations="5"><flag contact="disable"/></option><worldbody>
      <flexcomp name="cloth" type="grid" count="{n} {n} 1" spacing="{SPACING} {SPACING} {SPACING}" pos="0 0 40"
                radius="0.05" dim="2" mass="{MASS * n * n}">
        <elasticity young="2000" poisson="0.2" thickness="0.1" damping="0.01"/>
        <contact selfcollide="none" conaffinity="0" contype="0"/>
        <pin id="{pins}"/>
      </flexcomp></worldbody></mujoco>"""  # noqa: E501
    try:
        model = mujoco.MjModel.from_xml_string(xml)
    except ValueError as error:
        print(f"  mujoco flex scene could not be built: {error}")
        return None
    data = mujoco.MjData(model)
    mujoco.mj_step(model, data, nstep=5)
    steps, start = 0, time.process_time()
    while time.process_time() - start < budget:
        mujoco.mj_step(model, data, nstep=20)
        steps += 20
    return steps / (time.process_time() - start)


if wp is not None:

    @wp.kernel
    def _warp_springs(
        x: wp.array(dtype=wp.vec3),
        pairs: wp.array(dtype=wp.int32, ndim=2),
        rest: wp.array(dtype=float),
        k: float,
        force: wp.array(dtype=wp.vec3),
    ):
        s = wp.tid()
        a = pairs[s, 0]
        b = pairs[s, 1]
        d = x[b] - x[a]
        length = wp.length(d)
        f = d * (k * (length - rest[s]) / wp.max(length, 1.0e-12))
        wp.atomic_add(force, a, f)
        wp.atomic_sub(force, b, f)

    @wp.kernel
    def _warp_euler(
        x: wp.array(dtype=wp.vec3),
        v: wp.array(dtype=wp.vec3),
        force: wp.array(dtype=wp.vec3),
        fixed: wp.array(dtype=wp.int32),
        mass: float,
        gravity: wp.vec3,
        friction: float,
        h: float,
    ):
        i = wp.tid()
        f = force[i] + gravity * mass
        force[i] = wp.vec3(0.0, 0.0, 0.0)
        if fixed[i] == 0:
            vi = v[i]
            speed = wp.length(vi)
            if speed > 0.0:
                f = f - vi * (wp.min(friction * wp.length(f), mass * speed / h) / speed)
            x[i] = x[i] + vi * h
            v[i] = vi + f * (h / mass)


def warp_rate(n: int, budget: float = 1.0) -> float | None:
    """Warp CPU backend on the same sheet (springs + forward Euler kernels); None without
    warp-lang."""
    if wp is None:
        return None
    wp.config.quiet = True
    wp.init()
    model = hanging(n)
    device = "cpu"
    x = wp.array(model.rest_positions.astype(np.float32), dtype=wp.vec3, device=device)
    v = wp.zeros(model.size, dtype=wp.vec3, device=device)
    force = wp.zeros(model.size, dtype=wp.vec3, device=device)
    pairs = wp.array(model.springs.astype(np.int32), dtype=wp.int32, device=device)
    rest = wp.array(model.spring_rest.astype(np.float32), dtype=float, device=device)
    fixed = wp.array(model.fixed.astype(np.int32), dtype=wp.int32, device=device)
    gravity = wp.vec3(0.0, 0.0, -9.81)

    def step():
        wp.launch(
            _warp_springs, dim=len(model.springs), inputs=[x, pairs, rest, K, force], device=device
        )
        wp.launch(
            _warp_euler,
            dim=model.size,
            inputs=[x, v, force, fixed, MASS, gravity, FRICTION, H],
            device=device,
        )

    step()
    wp.synchronize()
    steps, start = 0, time.process_time()
    while time.process_time() - start < budget:
        for _ in range(20):
            step()
        steps += 20
    wp.synchronize()
    return steps / (time.process_time() - start)


def _cell(value: float | None, width: int = 9, digits: int = 0) -> str:
    return f"{value:{width}.{digits}f}" if value else f"{'n/a':>{width}}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[20, 100])
    parser.add_argument(
        "--seconds", type=float, default=2.0, help="simulated seconds per cloth run"
    )
    parser.add_argument(
        "--rounds", type=int, default=3, help="interleaved rounds; the best rate of each is kept"
    )
    args = parser.parse_args()
    import mujoco

    print(
        f"mujoco {mujoco.__version__}, warp {wp.__version__ if wp else 'not installed'}; steps per "
        f"CPU second, best of {args.rounds}"
    )
    print(
        f"{'grid':>8} {'run':>9} {'run-noSL':>9} {'implicit':>9} {'numpy':>9} {'mujoco':>9} "
        f"{'warp':>9} {'run/numpy':>10} {'run/mj':>7} {'run/warp':>9} {'noSL/numpy':>11} "
        f"{'noSL/warp':>10}"
    )
    for n in args.sizes:
        contenders = {
            "run": lambda: run_rate(n, args.seconds),
            "run_free": lambda: run_rate(n, args.seconds, "--strain-limit", "0"),
            "implicit": lambda: run_rate(
                n, 2 * args.seconds, "--integrator", "implicit", time_step=1 / 60
            ),
            "numpy": lambda: numpy_rate(n),
            "mujoco": lambda: mujoco_rate(n),
            "warp": lambda: warp_rate(n),
        }
        best: dict[str, float | None] = {}
        for _ in range(args.rounds):
            for name, measure in contenders.items():
                rate = measure()
                best[name] = None if rate is None else max(rate, best.get(name) or 0.0)
        run, run_free, implicit, numpy, mj, warp = best.values()

        def ratio(a, b, width):
            return f"{a / b:{width}.2f}" if b else f"{'n/a':>{width}}"

        print(
            f"{n:>4}x{n:<3} {run:9.0f} {run_free:9.0f} {implicit:9.1f} {numpy:9.0f} {_cell(mj)} "
            f"{_cell(warp)} {ratio(run, numpy, 10)} {ratio(run, mj, 7)} {ratio(run, warp, 9)} "
            f"{ratio(run_free, numpy, 11)} {ratio(run_free, warp, 10)}",
            flush=True,
        )


if __name__ == "__main__":
    main()
