"""UsdRender products and vars: what `gi render SCENE` writes without -o when the stage's render
settings declare RenderProducts. Each product is one EXR: its productName (frame tokens
substituted), resolution, camera and data window, and one named set of channels per RenderVar, in
the var's data type.

A var's sourceName picks what the renderer computes, its dataType how many channels and how they
are stored: renderer/render_vars.h holds those rules for both hosts (gi._core.render_var_layout).
Problems warn naming the prim and leave out only what they
concern: an unknown sourceName or dataType skips that var, a camera that is not there falls back to
the render settings' camera, a data window outside the image is clipped to it."""
from dataclasses import dataclass, field

import numpy as np
from pxr import UsdGeom, UsdRender

from .errors import SceneError
from .loader import image_framing, relationship_targets
from .loader import render_settings as stage_render_settings
from .render import require_core

FLOAT_MAX = np.finfo(np.float32).max


@dataclass
class Var:
    path: str
    name: str         # the layer name (the var prim's name); the beauty is written as plain R, G, B
    source: str       # RenderResult attribute
    channels: tuple   # suffixes, e.g. ('R', 'G', 'B') or ('',)
    half: bool


@dataclass
class Product:
    path: str
    name: str                  # productName, frame tokens not yet substituted
    resolution: tuple          # (width, height)
    camera: str                # camera prim path ('' = the render settings' / the loaded scene's)
    data_window_ndc: tuple     # (xmin, ymin, xmax, ymax), y up as UsdRender has it
    framing: tuple             # (aspectRatioConformPolicy, pixelAspectRatio), the settings' unless authored
    vars: list = field(default_factory=list)


def settings_prim(stage, requested, file):
    """The RenderSettings to use: `requested` (--settings), else the stage's renderSettingsPrimPath,
    else the first on the stage; None when there is none. SceneError for a bad `requested`."""
    if requested:
        prim = stage.GetPrimAtPath(requested) if requested.startswith("/") else None
        if not prim or not prim.IsA(UsdRender.Settings):
            raise SceneError(f"{file}: --settings {requested} is not a RenderSettings prim")
        return UsdRender.Settings(prim)
    return stage_render_settings(stage)


def _attribute(schema_attr, time, fallback):
    value = schema_attr.Get(time) if schema_attr and schema_attr.HasAuthoredValue() else None
    return fallback if value is None else value


def read_var(prim, warn, beauty_taken):
    core = require_core()
    var = UsdRender.Var(prim)
    path = str(prim.GetPath())
    source = str(var.GetSourceNameAttr().Get() or "")
    data_type = str(var.GetDataTypeAttr().Get() or "")
    try:
        attribute, suffixes, half = core.render_var_layout(source, data_type)
    except ValueError as problem:
        warn(path, f"{problem}; var skipped")
        return None
    return Var(path, core.render_var_layer(prim.GetName(), attribute, beauty_taken), attribute, tuple(suffixes), half)


def read_products(stage, settings, time, camera_override, warn):
    """The settings' products (authored order) with their vars; [] when it declares none."""
    if settings is None:
        return []
    base_resolution = tuple(_attribute(settings.GetResolutionAttr(), time, (512, 512)))
    base_camera = camera_override or next((str(t) for t in relationship_targets(settings.GetCameraRel(), warn)), "")
    base_framing = image_framing(settings, time, None, lambda path, message: None)  # the loader warns
    products = []
    for target in relationship_targets(settings.GetProductsRel(), warn):
        prim = stage.GetPrimAtPath(target)
        if not prim or not prim.IsA(UsdRender.Product):
            warn(str(settings.GetPath()), f"products: {target} is not a RenderProduct; skipped")
            continue
        product = UsdRender.Product(prim)
        path = str(prim.GetPath())
        camera = camera_override or next((str(t) for t in relationship_targets(product.GetCameraRel(), warn)), base_camera)
        camera_prim = stage.GetPrimAtPath(camera) if camera else None
        if camera and not (camera_prim and camera_prim.IsA(UsdGeom.Camera)):
            warn(path, f"camera {camera} does not exist or is not a camera; using "
                       f"{base_camera or 'the render settings camera'}")
            camera = base_camera if camera != base_camera else ""
        resolution = tuple(int(v) for v in _attribute(product.GetResolutionAttr(), time, base_resolution))
        framing = image_framing(product, time, base_framing, warn)
        ndc = tuple(float(v) for v in _attribute(product.GetDataWindowNDCAttr(), time,
                                                 _attribute(settings.GetDataWindowNDCAttr(), time, (0, 0, 1, 1))))
        out = Product(path, str(product.GetProductNameAttr().Get(time) or ""), resolution, camera, ndc, framing)
        if not out.name:
            warn(path, "no productName; product skipped")
            continue
        for var_path in relationship_targets(product.GetOrderedVarsRel(), warn):
            var_prim = stage.GetPrimAtPath(var_path)
            if not var_prim or not var_prim.IsA(UsdRender.Var):
                warn(path, f"orderedVars: {var_path} is not a RenderVar; skipped")
                continue
            var = read_var(var_prim, warn, any(v.name == "" for v in out.vars))
            if var is not None:
                out.vars.append(var)
        if not out.vars:
            warn(path, "no var this renderer can write; product skipped")
            continue
        products.append(out)
    return products


def pixel_window(product, warn):
    """dataWindowNDC as pixels (x0, y0, x1, y1), row 0 at the top: the pixels whose centres it
    holds, clipped to the image (renderer/pixel_window.h, hdGi's rule too). A window reaching
    outside the image or holding no pixel warns naming the product."""
    width, height = product.resolution
    window, problem = require_core().data_window_pixels(product.data_window_ndc, width, height)
    if problem:
        warn(product.path, problem)
    return window


def product_planes(product, result):
    """(pixels (h, w, C) float32 of the result's data window, channel names, half flags)."""
    x0, y0, x1, y1 = result.data_window
    planes, names, half = [], [], []
    for var in product.vars:
        image = np.asarray(getattr(result, var.source))[y0:y1, x0:x1].astype(np.float32)
        if var.source == "depth":  # no Inf in the file, as write_exr
            image = np.where(np.isfinite(image), image, FLOAT_MAX).astype(np.float32)
        image = image.reshape(image.shape[0], image.shape[1], -1)
        for c, suffix in enumerate(var.channels):
            planes.append(image[..., c])
            names.append(require_core().channel_name(var.name, suffix))
            half.append(var.half)
    return np.ascontiguousarray(np.stack(planes, axis=-1)), names, half
