"""The descriptor classes the loader fills: gi._core's when the core is built, otherwise pure-Python
stand-ins with the same fields and defaults (so the loader, `gi inspect` and the tests work
without the compiled renderer). The stand-ins read USD's defaults from the schemas and shader
definitions themselves rather than restating them."""
from dataclasses import dataclass, field

import numpy as np


def _identity():
    return np.eye(4, dtype=np.float64)


def _spec_default(shader, name):
    """The default of input `name` of the UsdPreviewSurface-family node `shader`, from its Sdr
    definition (the spec's; renderer/material.h and texture.h hold the same for the compiled core)."""
    def default():
        from pxr import Sdr
        value = Sdr.Registry().GetShaderNodeByIdentifier(shader).GetShaderInput(name).GetDefaultValue()
        if isinstance(value, str):
            return value
        if isinstance(value, int):
            return bool(value)  # useSpecularWorkflow
        return tuple(float(v) for v in value) if hasattr(value, "__len__") else float(value)
    return field(default_factory=default)


@dataclass
class _TextureDesc:
    file: str = ""
    wrap_s: str = _spec_default("UsdUVTexture", "wrapS")
    wrap_t: str = _spec_default("UsdUVTexture", "wrapT")
    scale: tuple = _spec_default("UsdUVTexture", "scale")
    bias: tuple = _spec_default("UsdUVTexture", "bias")
    fallback: tuple = _spec_default("UsdUVTexture", "fallback")
    channel: str = "rgb"
    source_color_space: str = _spec_default("UsdUVTexture", "sourceColorSpace")
    st_rotation: float = _spec_default("UsdTransform2d", "rotation")
    st_scale: tuple = _spec_default("UsdTransform2d", "scale")
    st_translation: tuple = _spec_default("UsdTransform2d", "translation")


@dataclass
class _MaterialDesc:
    name: str = "default"
    diffuse_color: tuple = _spec_default("UsdPreviewSurface", "diffuseColor")
    emissive_color: tuple = _spec_default("UsdPreviewSurface", "emissiveColor")
    use_specular_workflow: bool = _spec_default("UsdPreviewSurface", "useSpecularWorkflow")
    specular_color: tuple = _spec_default("UsdPreviewSurface", "specularColor")
    metallic: float = _spec_default("UsdPreviewSurface", "metallic")
    roughness: float = _spec_default("UsdPreviewSurface", "roughness")
    clearcoat: float = _spec_default("UsdPreviewSurface", "clearcoat")
    clearcoat_roughness: float = _spec_default("UsdPreviewSurface", "clearcoatRoughness")
    opacity: float = _spec_default("UsdPreviewSurface", "opacity")
    opacity_mode: str = _spec_default("UsdPreviewSurface", "opacityMode")
    opacity_threshold: float = _spec_default("UsdPreviewSurface", "opacityThreshold")
    ior: float = _spec_default("UsdPreviewSurface", "ior")
    diffuse_color_texture: _TextureDesc = field(default_factory=_TextureDesc)
    emissive_color_texture: _TextureDesc = field(default_factory=_TextureDesc)
    specular_color_texture: _TextureDesc = field(default_factory=_TextureDesc)
    metallic_texture: _TextureDesc = field(default_factory=_TextureDesc)
    roughness_texture: _TextureDesc = field(default_factory=_TextureDesc)
    opacity_texture: _TextureDesc = field(default_factory=_TextureDesc)
    normal_texture: _TextureDesc = field(default_factory=_TextureDesc)


@dataclass
class _LightDesc:
    name: str = ""
    kind: str = "rect"
    color: tuple = (1.0, 1.0, 1.0)
    intensity: float = 1.0
    exposure: float = 0.0
    normalize: bool = False
    width: float = 1.0
    height: float = 1.0
    radius: float = 0.5
    length: float = 1.0
    angle: float = 0.53
    texture_file: str = ""
    transform: np.ndarray = field(default_factory=_identity)
    motion_transforms: object = None   # (steps, 4, 4) over the shutter when the light moves
    visible_to_camera: bool = True


def _camera_fallback(attribute):
    """UsdGeomCamera's fallback value of `attribute`, from the schema itself (renderer/camera_desc.h
    holds the same defaults for the compiled core)."""
    def fallback():
        from pxr import Usd
        value = Usd.SchemaRegistry().FindConcretePrimDefinition("Camera").GetAttributeFallbackValue(attribute)
        return value if isinstance(value, str) else float(value)
    return field(default_factory=fallback)


@dataclass
class _CameraDesc:
    name: str = ""
    projection: str = _camera_fallback("projection")
    focal_length: float = _camera_fallback("focalLength")
    horizontal_aperture: float = _camera_fallback("horizontalAperture")
    vertical_aperture: float = _camera_fallback("verticalAperture")
    horizontal_aperture_offset: float = _camera_fallback("horizontalApertureOffset")
    vertical_aperture_offset: float = _camera_fallback("verticalApertureOffset")
    f_stop: float = _camera_fallback("fStop")
    focus_distance: float = _camera_fallback("focusDistance")
    clipping_range: tuple = (1e-4, 1e30)
    shutter_open: float = 0.0
    shutter_close: float = 0.0
    transform: np.ndarray = field(default_factory=_identity)
    motion_transforms: object = None   # (steps, 4, 4) over the shutter when the camera moves


class CountingScene:
    """Accepts what a gi._core.Scene accepts and only hands out ids: lets `gi inspect` (and anything
    that just needs the loader's counts and warnings) run without the compiled core."""

    def __init__(self):
        self._next_id = {}

    def _new_id(self, kind):
        self._next_id[kind] = self._next_id.get(kind, -1) + 1
        return self._next_id[kind]

    def add_material(self, material):
        return self._new_id("material")

    def add_prototype(self, name):
        return self._new_id("prototype")

    def add_mesh(self, name, positions, indices, *args, **kwargs):
        return self._new_id("mesh")

    def add_sphere(self, name, center, radius, *args, **kwargs):
        return self._new_id("sphere")

    def add_instance(self, prototype, transform, name="", motion_transforms=None):
        return self._new_id("instance")

    def add_light(self, light):
        return self._new_id("light")

    def set_camera(self, camera):
        pass

    def commit(self):
        pass

    def warnings(self):
        return []

    def stats(self):
        return {}


PYTHON_DESCRIPTORS = {"TextureDesc": _TextureDesc, "MaterialDesc": _MaterialDesc, "LightDesc": _LightDesc,
                      "CameraDesc": _CameraDesc}

# The loader creates descriptors as descriptors.<Name>() so that tests can swap these names.
try:
    from ._core import CameraDesc, LightDesc, MaterialDesc, TextureDesc  # noqa: F401
    HAVE_CORE = True
except ImportError:
    TextureDesc, MaterialDesc, LightDesc, CameraDesc = _TextureDesc, _MaterialDesc, _LightDesc, _CameraDesc
    HAVE_CORE = False


def indexed_name(base, index, count):
    """The name of instance `index` of `count` known only by index (gi._core.indexed_name,
    renderer/scene.h: zero-padded so that names sort as indices do); without the compiled core,
    which renders nothing, base[index]."""
    if not HAVE_CORE:
        return f"{base}[{index}]"
    from ._core import indexed_name as core_indexed_name
    return core_indexed_name(base, index, count)


def new_scene():
    """A gi._core.Scene; ImportError (saying so) when the core is not built."""
    if not HAVE_CORE:
        raise ImportError("gi._core (the compiled renderer) is not built; run scripts/build.sh, "
                          "or pass a scene object to load_stage")
    from ._core import Scene
    return Scene()
