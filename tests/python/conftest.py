import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
CORNELL = ROOT / "scenes" / "cornell" / "cornell.usda"


@pytest.fixture
def cornell():
    return CORNELL


def run_gi(*args, check=True):
    """Runs the gi CLI in a subprocess, as a user would."""
    proc = subprocess.run([sys.executable, "-m", "gi", *map(str, args)], capture_output=True, text=True)
    if check and proc.returncode != 0:
        raise AssertionError(f"gi {' '.join(map(str, args))} failed ({proc.returncode}):\n{proc.stderr}")
    return proc


def render(scene_path, integrator="path", spp=16, seed=0, resolution=(32, 32), **params):
    from gi.cli import render_scene
    result, loaded, _ = render_scene(str(scene_path), integrator, params, spp, seed, resolution=resolution)
    return np.asarray(result.color), result, loaded
