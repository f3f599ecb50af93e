#!/usr/bin/env python3
"""Fuzzes the USD loader and the renderer behind it with mutated scenes.

Each iteration takes one of the project's scenes (scenes/**/*.usda under a size limit, the stress
scenes and the mesh parity stages of tests/parity included), applies a few seeded mutations to its text (numbers replaced by NaN, Inf, 0,
huge or tiny values; array elements dropped; lines deleted, duplicated or swapped; attribute types
and tokens changed), loads it with gi.loader.load_stage (subdivision meshes refined 0, 1 or 2 times) and renders it at 8x8, 1 spp with a
random integrator. A load may fail only with SceneError; a render must finish with finite pixels.

A crash (a signal in the renderer) kills the process: the scene being tried is always written
to <out>/current.usda first, with its seed and mutations in current.txt, so it can be replayed:

    .venv/bin/python tests/fuzz/fuzz_loader.py --replay out/fuzz/current.usda --refine-level L

Usage: fuzz_loader.py [--seed S] [--iterations N] [--seconds T] [--out DIR]
Exit status 0 when every iteration passed, 1 when one failed (its scene kept in DIR/failures)."""
import argparse
import json
import random
import re
import shutil
import sys
import time
import traceback
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
# This checkout's gi; its compiled core from the checkout if a build put it there, else from the
# installed package (as tests/python/conftest.py does).
sys.path.insert(0, str(ROOT / "python"))
import site  # noqa: E402

import gi  # noqa: E402

if not any((ROOT / "python" / "gi").glob("_core*.so")):
    gi.__path__.extend(str(Path(d) / "gi") for d in site.getsitepackages() if any((Path(d) / "gi").glob("_core*.so")))

import numpy as np  # noqa: E402

from gi import _core  # noqa: E402
from gi.render import render_settings  # noqa: E402
from gi.errors import SceneError  # noqa: E402
from gi.loader import load_stage  # noqa: E402

MAX_SCENE_BYTES = 64 * 1024
SLOW_SECONDS = 5.0
NUMBER = re.compile(r"(?<![\w.])-?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?(?![\w.])")
SPECIAL_NUMBERS = ["nan", "inf", "-inf", "0", "-0", "-1", "1e30", "-1e30", "1e-30", "3.5e38", "1e-45",
                   "2147483647", "-2147483648", "4294967296", "1e300", "0.5", "1e5", "-1e-7"]
TYPES = ["float", "double", "int", "bool", "token", "string", "float3", "double3", "color3f", "point3f",
         "normal3f", "texCoord2f", "float2", "int[]", "float[]", "point3f[]", "normal3f[]", "token[]",
         "matrix4d", "asset", "half", "uint"]
TYPE = re.compile(r"\b(?:float|double|int|bool|token|string|float2|float3|double3|color3f|point3f|normal3f|"
                  r"texCoord2f|matrix4d|asset)(?:\[\])?(?= )")
TOKENS = ['"vertex"', '"faceVarying"', '"uniform"', '"constant"', '"varying"', '"leftHanded"', '"orthographic"',
          '"presence"', '"transparent"', '"X"', '"bogus"', '""', '"Y"']
STRING = re.compile(r'"[A-Za-z_]*"')


def scenes():
    """The project's small text scenes; those sublayering files `gi import` generates (not in the
    repository) are left out, so a seed means the same run on every checkout. (The mutated copies
    are written to the output folder: relative texture paths then miss, which is one more case.)"""
    candidates = [*(ROOT / "scenes").rglob("*.usda"), *(ROOT / "tests" / "parity").glob("*.usda")]
    return sorted(p for p in candidates if p.stat().st_size <= MAX_SCENE_BYTES and "@generated/" not in p.read_text())


# -- mutations: each takes (text, rng) and returns (text, description) -----------------------------

def replace_number(text, rng):
    matches = list(NUMBER.finditer(text))
    if not matches:
        return text, "no number"
    m = rng.choice(matches)
    value = rng.choice(SPECIAL_NUMBERS) if rng.random() < 0.7 else repr(float(m.group()) * rng.choice([-1, 1e-6, 1e6, 1e20]))
    return text[:m.start()] + value + text[m.end():], f"number {m.group()!r} at {m.start()} -> {value}"


def drop_array_element(text, rng):
    arrays = [m for m in re.finditer(r"\[([^\[\]\n]+)\]", text)]
    if not arrays:
        return text, "no array"
    m = rng.choice(arrays)
    items = m.group(1).split(", ")
    if len(items) < 2:
        return text, "short array"
    i = rng.randrange(len(items))
    body = ", ".join(items[:i] + items[i + 1:])
    return text[:m.start(1)] + body + text[m.end(1):], f"array at {m.start()} lost element {i}"


def edit_lines(text, rng):
    """Deletes, duplicates or swaps attribute lines (a brace or bracket moved mostly makes a file
    the parser rejects, which tests little)."""
    lines = text.split("\n")
    attributes = [k for k, line in enumerate(lines) if " = " in line and not any(c in line for c in "{}()")]
    if len(attributes) < 2:
        return text, "short"
    i, j = rng.choice(attributes), rng.choice(attributes)
    kind = rng.choice(["delete", "duplicate", "swap"])
    if kind == "delete":
        del lines[i]
    elif kind == "duplicate":
        lines.insert(j, lines[i])
    else:
        lines[i], lines[j] = lines[j], lines[i]
    return "\n".join(lines), f"{kind} line {i} ({j})"


def retype(text, rng):
    matches = list(TYPE.finditer(text))
    if not matches:
        return text, "no type"
    m = rng.choice(matches)
    new = rng.choice(TYPES)
    return text[:m.start()] + new + text[m.end():], f"type {m.group()} at {m.start()} -> {new}"


def retoken(text, rng):
    matches = list(STRING.finditer(text))
    if not matches:
        return text, "no token"
    m = rng.choice(matches)
    new = rng.choice(TOKENS)
    return text[:m.start()] + new + text[m.end():], f"token {m.group()} at {m.start()} -> {new}"


def flip_character(text, rng):
    i = rng.randrange(len(text))
    c = rng.choice("()[]{}<>,.=-\"0x \n")
    return text[:i] + c + text[i + 1:], f"char {i} -> {c!r}"


MUTATIONS = [(replace_number, 6), (drop_array_element, 2), (edit_lines, 2), (retype, 1), (retoken, 1),
             (flip_character, 1)]


def mutate(text, rng):
    functions, weights = zip(*MUTATIONS)
    done = []
    for _ in range(rng.choice([1, 1, 2, 3, 5])):
        text, description = rng.choices(functions, weights)[0](text, rng)
        done.append(description)
    return text, done


# -- running ---------------------------------------------------------------------------------------

INTEGRATORS = [info["name"] for info in _core.integrators()]
TAKES = {info["name"]: {p["name"] for p in info["params"]} for info in _core.integrators()}
FAST = {"photons": 400, "causticPhotons": 400, "paths": 8, "finalGatherSamples": 2, "refinementRounds": 10,
        "autoHorizon": 0.5}


def try_scene(path, integrator, refine_level=0):
    """'rejected' (SceneError), or 'rendered'; raises AssertionError (or anything else) on a failure."""
    try:
        loaded = load_stage(str(path), refine_level=refine_level)
    except SceneError:
        return "rejected"
    params = {k: v for k, v in FAST.items() if k in TAKES[integrator]}
    settings = render_settings(loaded, integrator, params, 1, 0, 0, 0.0, (8, 8), "box")
    result = _core.render(loaded.scene, settings)
    color = np.asarray(result.color)
    assert np.isfinite(color).all(), "NaN or Inf pixel"
    assert result.stats["non_finite_samples"] == 0, f"{result.stats['non_finite_samples']:.0f} non-finite samples"
    return "rendered"


def run(seed, iterations, seconds, out):
    out.mkdir(parents=True, exist_ok=True)
    sources = scenes()
    rng = random.Random(seed)
    start = time.monotonic()
    counts = {"rendered": 0, "rejected": 0, "failed": 0}
    iteration = 0
    while (iterations is None or iteration < iterations) and (seconds is None or time.monotonic() - start < seconds):
        source = rng.choice(sources)
        text, mutations = mutate(source.read_text(), rng)
        integrator = rng.choice(INTEGRATORS)
        # Drawn apart from `rng`, so that a seed keeps its scenes, mutations and integrators.
        refine_level = random.Random(f"{seed}-{iteration}").choice([0, 1, 2])
        # A new name each time: USD keeps layers it has opened and would not read the file again.
        current = out / f"fuzz_{seed}_{iteration}.usda"
        current.write_text(text)
        (out / "current.usda").write_text(text)
        (out / "current.txt").write_text(json.dumps({"seed": seed, "iteration": iteration, "source": str(source),
                                                     "integrator": integrator, "refine_level": refine_level,
                                                     "mutations": mutations}, indent=1))
        began = time.monotonic()
        try:
            counts[try_scene(current, integrator, refine_level)] += 1
        except Exception:  # noqa: BLE001  -- every other outcome is a finding
            counts["failed"] += 1
            (out / "failures").mkdir(exist_ok=True)
            kept = out / "failures" / f"seed{seed}_{iteration}.usda"
            shutil.copy(current, kept)
            print(f"FAIL {kept} ({source.name}, {integrator}, refine level {refine_level}, {mutations}):\n"
                  f"{traceback.format_exc()}", flush=True)
        finally:
            current.unlink(missing_ok=True)
        took = time.monotonic() - began
        if took > SLOW_SECONDS:  # not a failure, but worth a look: a mutation that makes a render slow
            (out / "slow").mkdir(exist_ok=True)
            (out / "slow" / f"seed{seed}_{iteration}.usda").write_text(text)
            print(f"SLOW {took:.1f} s: seed {seed} iteration {iteration} ({source.name}, {integrator}, {mutations})",
                  flush=True)
        iteration += 1
    elapsed = time.monotonic() - start
    print(f"fuzz: seed {seed}, {iteration} iterations in {elapsed:.1f} s over {len(sources)} scenes: "
          f"{counts['rendered']} rendered, {counts['rejected']} rejected as not USD, {counts['failed']} failed")
    return counts


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--iterations", type=int)
    parser.add_argument("--seconds", type=float)
    parser.add_argument("--out", type=Path, default=ROOT / "out" / "fuzz")
    parser.add_argument("--replay", type=Path, help="load and render one scene under every integrator")
    parser.add_argument("--refine-level", type=int, default=0, help="with --replay: subdivision refine level")
    args = parser.parse_args(argv)
    if args.replay:
        for integrator in INTEGRATORS:
            print(integrator, try_scene(args.replay, integrator, args.refine_level), flush=True)
        return 0
    if args.iterations is None and args.seconds is None:
        args.iterations = 200
    counts = run(args.seed, args.iterations, args.seconds, args.out)
    return 1 if counts["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
