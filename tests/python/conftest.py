import os
import site
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
SOURCE = ROOT / "python"
CORNELL = ROOT / "scenes" / "cornell" / "cornell.usda"


def has_core(package_dir):
    return any(Path(package_dir).glob("_core*.so"))


def installed_package_dirs():
    return [Path(d) / "gi" for d in site.getsitepackages()]


# The tests test this checkout's Python code (python/gi), not an installed copy of it. gi._core comes
# from the checkout when a build put it there (python/gi/_core*.so), else from the installed package.
SOURCE_HAS_CORE = has_core(SOURCE / "gi")
sys.path.insert(0, str(SOURCE))
import gi  # noqa: E402

if not SOURCE_HAS_CORE:
    gi.__path__.extend(str(d) for d in installed_package_dirs() if has_core(d))


@pytest.fixture
def cornell():
    return CORNELL


def run_gi(*args, check=True, cwd=None):
    """Runs the gi CLI in a subprocess, as a user would (this checkout's gi when it has a core)."""
    env = dict(os.environ)
    if SOURCE_HAS_CORE:
        env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(SOURCE), env.get("PYTHONPATH")]))
    proc = subprocess.run([sys.executable, "-m", "gi", *map(str, args)], capture_output=True, text=True, env=env,
                          cwd=cwd)
    if check and proc.returncode != 0:
        raise AssertionError(f"gi {' '.join(map(str, args))} failed ({proc.returncode}):\n{proc.stderr}")
    return proc


def render(scene_path, integrator="path", spp=16, seed=0, resolution=(32, 32), **params):
    from gi.render import render_scene
    result, loaded, _ = render_scene(str(scene_path), integrator, params, spp, seed, resolution=resolution)
    return np.asarray(result.color), result, loaded


def new_stage(tmp_path, name="scene.usda"):
    """A new stage file in tmp_path, Y up, with a camera at z = 5 looking down -z."""
    from pxr import Gf, Usd, UsdGeom
    path = tmp_path / name
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.Camera.Define(stage, "/Camera").AddTranslateOp().Set(Gf.Vec3d(0, 0, 5))
    return stage, path


class RecordingScene:
    """Stands in for gi._core.Scene in loader tests: records every call and hands out ids, so the
    tests run without the compiled core."""

    def __init__(self):
        self.materials, self.prototypes, self.meshes, self.spheres = [], [], [], []
        self.instances, self.lights, self.cameras = [], [], []

    @staticmethod
    def _record(calls, call):
        calls.append(call)
        return len(calls) - 1

    def add_material(self, material):
        return self._record(self.materials, material)

    def add_prototype(self, name):
        return self._record(self.prototypes, name)

    def add_mesh(self, name, positions, indices, normals=None, uvs=None, material=-1, transform=None,
                 double_sided=True, prototype=-1, motion_points=None, motion_transforms=None):
        return self._record(self.meshes, SimpleNamespace(
            name=name, positions=positions, indices=indices, normals=normals, uvs=uvs, material=material,
            transform=transform, double_sided=double_sided, prototype=prototype, motion_points=motion_points,
            motion_transforms=motion_transforms))

    def add_sphere(self, name, center, radius, material=-1, transform=None, prototype=-1, motion_transforms=None):
        return self._record(self.spheres, SimpleNamespace(
            name=name, center=tuple(center), radius=radius, material=material, transform=transform,
            prototype=prototype, motion_transforms=motion_transforms))

    def add_instance(self, prototype, transform, name="", motion_transforms=None):
        return self._record(self.instances, SimpleNamespace(prototype=prototype, transform=transform, name=name,
                                                            motion_transforms=motion_transforms))

    def add_light(self, light):
        return self._record(self.lights, light)

    def set_camera(self, camera):
        self.cameras.append(camera)

    def commit(self):
        pass

    def warnings(self):
        return []

    def stats(self):
        return {}

    # -- look-ups for the tests --
    def mesh(self, name):
        return next(m for m in self.meshes if m.name == name)

    def material_of(self, name):
        index = next(x.material for x in self.meshes + self.spheres if x.name == name)
        return self.materials[index] if index >= 0 else None


@pytest.fixture
def fake_scene(monkeypatch):
    """A RecordingScene, with the loader making pure-Python descriptors (gi.descriptors' stand-ins)
    so that the tests neither need the compiled core nor depend on its objects."""
    from gi import descriptors
    for name, python_class in descriptors.PYTHON_DESCRIPTORS.items():
        monkeypatch.setattr(descriptors, name, python_class)
    return RecordingScene()
