"""A Mitsuba 3 scene built from exactly what gi's loader reads from a USD stage, so that Mitsuba and
gi render the same picture (issue 17: the peer benchmark; issue 19: independent references).

gi's loader (gi.loader.load_stage) hands every mesh, sphere, material, light and the camera to a
scene object; RecordingScene keeps them, and mitsuba_scene() turns them into a Mitsuba scene:

- meshes: mi.Mesh in world space (instances flattened), st's t flipped (Mitsuba's v runs down);
  vertex normals that face away from (or lie in) their triangle: see shading_normals_as_gi;
- materials (UsdPreviewSurface as gi reads it, renderer/material.cpp, bsdf.cpp): black specular
  colour -> `diffuse`; otherwise (a specular lobe) -> `usd_specular_workflow`, a Dr.Jit BSDF
  written here from UsdPreviewSurface's formulas (Lambert * (1 - max F(view)) + GGX with Schlick
  Fresnel from F0/F90 and height-correlated Smith masking); opaque BSDFs are `twosided` (gi shades
  the side the ray arrives on); opacity t < 1 in "transparent" mode -> `blendbsdf` of the opaque
  lobes (1 - t) and a `dielectric` / `roughdielectric` (t) whose transmission is tinted by the
  diffuse colour (gi tints every refraction; Mitsuba's rough dielectric masks with separable
  rather than height-correlated Smith, a difference only at grazing angles);
- lights: rect/disk/sphere -> shapes with an `area` emitter (one-sided, black behind, as gi's);
  dome and distant lights -> one `envmap` (Mitsuba allows one environment): the dome's radiance
  plus the sun's 0.53 degree disc painted into a lat-long map, its radiance set so the disc's
  irradiance equals gi's exactly. A `directional` emitter would be a delta light, which a path
  tracer cannot reach through smooth glass (Sibenik's sun only enters through its windows);
- camera: `perspective` with the same horizontal field of view after UsdGeomCamera's
  expandAperture fit, the USD camera frame (looking down -Z) turned to Mitsuba's (+Z, x left);
- film: box pixel filter (gi's default), linear RGB.

Anything the conversion cannot express (textured emission, normal maps, presence opacity,
clearcoat, rough glass, aperture offsets, depth of field) raises ConversionError naming it: a
silently different scene would make the comparison meaningless."""
import math
from dataclasses import dataclass

import numpy as np
from gi.descriptors import CountingScene

VARIANT = "llvm_ad_rgb"
SUN_MAP_WIDTH = 4096          # lat-long map columns: 0.088 degrees a pixel, the 0.53 degree sun ~6 pixels wide
SUN_SUPERSAMPLES = 16         # per pixel side, for the disc's coverage of each pixel
SMOOTH_ALPHA = 1e-3           # gi's GGX::kSmoothAlpha: below it a lobe is a perfect mirror / refraction


class ConversionError(Exception):
    pass


# -- recording what gi's loader reads ------------------------------------------------------------

@dataclass
class Shape:
    name: str
    material: int
    transform: np.ndarray          # (4, 4) row-vector, object -> world (or -> prototype)
    double_sided: bool
    prototype: int
    positions: np.ndarray = None   # meshes
    indices: np.ndarray = None
    normals: np.ndarray = None
    uvs: np.ndarray = None
    center: tuple = None           # spheres
    radius: float = 0.0


class RecordingScene(CountingScene):
    """Takes what gi._core.Scene takes (the loader's calls) and keeps it."""

    def __init__(self):
        super().__init__()
        self.materials, self.shapes, self.prototypes, self.lights = [], [], [], []
        self.instances = []   # (prototype, transform)
        self.camera = None
        self.framing = None  # the render settings' (conform policy, pixel aspect ratio); None: none
        # What could not be recorded. The loader turns a scene call's exception into a warning and
        # goes on (bad input never stops a render), so record() raises on these itself: a shape
        # left out would make the two renderers compare different scenes.
        self.failures = []

    def still(self, name, *motion):
        """Motion blur is not converted: the comparison is of still frames."""
        if any(m is not None for m in motion):
            self.failures.append(f"{name}: moves during the shutter; motion blur is not converted")
            raise ConversionError(self.failures[-1])

    def add_material(self, material):
        self.materials.append(material)
        return len(self.materials) - 1

    def add_prototype(self, name):
        self.prototypes.append(name)
        return len(self.prototypes) - 1

    def add_mesh(self, name, positions, indices, normals, uvs, material, transform, double_sided, prototype,
                 motion_points=None, motion_transforms=None):
        self.still(name, motion_points, motion_transforms)
        self.shapes.append(Shape(name, material, np.asarray(transform, np.float64), double_sided, prototype,
                                 np.asarray(positions, np.float64), np.asarray(indices, np.uint32),
                                 None if normals is None else np.asarray(normals, np.float64),
                                 None if uvs is None else np.asarray(uvs, np.float64)))
        return len(self.shapes) - 1

    def add_sphere(self, name, center, radius, material, transform, prototype, motion_transforms=None):
        self.still(name, motion_transforms)
        self.shapes.append(Shape(name, material, np.asarray(transform, np.float64), True, prototype,
                                 center=tuple(center), radius=float(radius)))
        return len(self.shapes) - 1

    def add_instance(self, prototype, transform, name="", motion_transforms=None):
        self.still(name, motion_transforms)
        self.instances.append((prototype, np.asarray(transform, np.float64)))
        return len(self.instances) - 1

    def add_light(self, light):
        self.lights.append(light)
        return len(self.lights) - 1

    def set_camera(self, camera):
        self.camera = camera


def record(path, camera=None):
    """(RecordingScene, gi.loader.LoadedScene) of a USD file, read by gi's own loader."""
    from gi.loader import load_stage
    scene = RecordingScene()
    loaded = load_stage(str(path), scene=scene, camera=camera)
    if scene.failures:
        raise ConversionError("; ".join(scene.failures))
    unread = [str(w) for w in loaded.warnings if "could not be read" in str(w)]
    if unread:  # e.g. a scene call this class does not take: the loader warns and leaves the prim out
        raise ConversionError(f"{path}: prims not recorded: " + "; ".join(unread[:3]))
    scene.framing = loaded.framing
    return scene, loaded


def world_shapes(recorded):
    """Every shape in world space: top-level shapes as they are, prototype shapes once per instance."""
    for shape in recorded.shapes:
        if shape.prototype < 0:
            yield shape, shape.transform
    for prototype, instance_transform in recorded.instances:
        for shape in recorded.shapes:
            if shape.prototype == prototype:
                yield shape, shape.transform @ instance_transform   # row vectors: object, then instance


# -- Mitsuba objects -----------------------------------------------------------------------------

def mitsuba():
    import drjit as dr
    import mitsuba as mi
    if mi.variant() != VARIANT:
        mi.set_variant(VARIANT)
    register_specular_workflow_bsdf(mi, dr)
    return mi, dr


def column_major(row_vector_matrix):
    """gi's (and USD's) row-vector matrix as the column-vector matrix Mitsuba's Transform4f takes."""
    return np.asarray(row_vector_matrix, np.float64).T


def luminance(rgb):
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]


def is_black(rgb):
    return max(rgb) <= 0


def texture_is_set(texture):
    return bool(texture.file)


def bitmap_texture(mi, texture, name):
    """A `bitmap` of a UsdUVTexture as gi reads it: decoded to linear (sRGB unless raw), then
    value * scale + bias (gi's Texture::eval), bilinear, repeat."""
    for attribute, identity in (("st_rotation", 0.0), ("st_scale", (1.0, 1.0)), ("st_translation", (0.0, 0.0))):
        if tuple(np.atleast_1d(getattr(texture, attribute))) != tuple(np.atleast_1d(identity)):
            raise ConversionError(f"{name}: texture {texture.file} has a UsdTransform2d; not converted")
    if (texture.wrap_s, texture.wrap_t) not in (("repeat", "repeat"), ("useMetadata", "useMetadata")):
        raise ConversionError(f"{name}: texture {texture.file} wraps {texture.wrap_s}/{texture.wrap_t}; not converted")
    bitmap = mi.Bitmap(texture.file)
    srgb = texture.source_color_space == "sRGB" or (texture.source_color_space == "auto" and
                                                   bitmap.component_format() == mi.Struct.Type.UInt8)
    linear = np.array(bitmap.convert(mi.Bitmap.PixelFormat.RGBA, mi.Struct.Type.Float32, srgb_gamma=False)
                      if srgb else bitmap.convert(mi.Bitmap.PixelFormat.RGBA, mi.Struct.Type.Float32,
                                                  srgb_gamma=bitmap.srgb_gamma()))
    if srgb and bitmap.srgb_gamma() is False:  # a file tagged linear, but sourceColorSpace says sRGB
        raise ConversionError(f"{name}: texture {texture.file} is tagged linear but read as sRGB")
    value = linear * np.asarray(texture.scale, np.float32) + np.asarray(texture.bias, np.float32)
    if texture.channel == "rgb":
        data = value[..., :3]
    else:
        data = np.repeat(value[..., "rgba".index(texture.channel)][..., None], 3, axis=2)
    return {"type": "bitmap", "bitmap": mi.Bitmap(np.ascontiguousarray(data, np.float32)), "raw": True,
            "filter_type": "bilinear", "wrap_mode": "repeat"}


def rgb(value):
    return {"type": "rgb", "value": [float(c) for c in value]}


def bsdf_dict(mi, material):
    """The Mitsuba BSDF of one gi MaterialDesc (see the module doc for the mapping)."""
    name = material.name
    for texture_name in ("specular_color_texture", "metallic_texture", "roughness_texture", "opacity_texture",
                         "normal_texture", "emissive_color_texture"):
        if texture_is_set(getattr(material, texture_name)):
            raise ConversionError(f"{name}: {texture_name} is not converted")
    if material.clearcoat > 0:
        raise ConversionError(f"{name}: clearcoat is not converted")
    if material.opacity_mode != "transparent" or material.opacity_threshold > 0:
        if material.opacity < 1:
            raise ConversionError(f"{name}: presence opacity is not converted")
    diffuse = (bitmap_texture(mi, material.diffuse_color_texture, name)
               if texture_is_set(material.diffuse_color_texture) else rgb(np.minimum(material.diffuse_color, 1)))
    transmission = 1 - material.opacity if material.opacity_mode == "transparent" else 0.0
    if transmission <= 0:
        return {"type": "twosided", "bsdf": opaque_lobes(material, diffuse)}
    if texture_is_set(material.diffuse_color_texture):
        raise ConversionError(f"{name}: textured transmission is not converted")
    # gi: opaque lobes (front side only: a transmitting surface is not flipped) weighted 1 - t,
    # a dielectric weighted t whose transmission is tinted by the diffuse colour.
    dielectric = {"type": "dielectric", "int_ior": float(material.ior), "ext_ior": 1.0,
                  "specular_transmittance": rgb(np.minimum(material.diffuse_color, 1))}
    alpha = material.roughness ** 2
    if alpha >= SMOOTH_ALPHA:
        dielectric.update(type="roughdielectric", distribution="ggx", alpha=float(alpha), sample_visible=True)
    if transmission >= 1:
        return dielectric
    return {"type": "blendbsdf", "weight": float(transmission), "bsdf_0": opaque_lobes(material, diffuse),
            "bsdf_1": dielectric}


def opaque_lobes(material, diffuse):
    """UsdPreviewSurface's opaque lobes: Lambert alone when there is no specular lobe."""
    name = material.name
    if material.use_specular_workflow:
        f0 = np.minimum(np.asarray(material.specular_color, np.float64), 1)
        f90 = min(max(50.0 * f0.max(), 0.0), 1.0)   # gi's (Filament's) rule: black specular, no grazing lobe
    else:
        r = (1 - material.ior) / (1 + material.ior)
        if material.metallic > 0:
            raise ConversionError(f"{name}: metallic > 0 is not converted")
        f0, f90 = np.full(3, r * r), 1.0
    if is_black(f0) and f90 == 0:
        return {"type": "diffuse", "reflectance": diffuse}
    if VARIANT.startswith("scalar"):
        raise ConversionError(f"{name}: the specular-workflow BSDF is Python, which a scalar variant calls per "
                              "sample; compare scalar variants on scenes without it (the Cornell box)")
    return {"type": "usd_specular_workflow", "diffuse": diffuse, "f0": rgb(f0), "f90": float(f90),
            "roughness": float(material.roughness)}


BLACK = {"type": "diffuse", "reflectance": {"type": "rgb", "value": 0.0}}


def light_radiance(light):
    return np.asarray(light.color, np.float64) * light.intensity * 2.0 ** light.exposure


def area_light_shape(mi, light):
    """A rect, disk or sphere light as a Mitsuba shape with an area emitter (gi's light.cpp)."""
    m = column_major(light.transform)
    radiance = np.maximum(light_radiance(light), 0)
    flip_to_minus_z = np.diag([1.0, -1.0, -1.0, 1.0])   # UsdLux lights face -Z; Mitsuba's face +Z
    if light.kind == "rect":
        local = np.diag([light.width / 2, light.height / 2, 1.0, 1.0])
        area = np.linalg.norm(np.cross(m[:3, 0] * light.width, m[:3, 1] * light.height))
        shape = {"type": "rectangle", "to_world": mi.ScalarTransform4f(m @ flip_to_minus_z @ local)}
    elif light.kind == "disk":
        scale = math.sqrt(np.linalg.norm(m[:3, 0]) * np.linalg.norm(m[:3, 1]))
        area = math.pi * (light.radius * scale) ** 2
        local = np.diag([light.radius, light.radius, 1.0, 1.0])
        shape = {"type": "disk", "to_world": mi.ScalarTransform4f(m @ flip_to_minus_z @ local)}
    elif light.kind == "sphere":
        radius = light.radius * abs(np.linalg.det(m[:3, :3])) ** (1 / 3)
        area = 4 * math.pi * radius ** 2
        shape = {"type": "sphere", "center": [float(v) for v in m[:3, 3]], "radius": float(radius)}
    else:
        raise ConversionError(f"{light.name}: {light.kind} lights are not converted")
    if light.normalize:
        radiance = radiance / area
    if not light.visible_to_camera:
        raise ConversionError(f"{light.name}: lights hidden from the camera are not converted")
    shape["bsdf"] = BLACK
    shape["emitter"] = {"type": "area", "radiance": rgb(radiance)}
    return shape


def sun_irradiance(light):
    """gi's DistantLight: irradiance at normal incidence (normalize on), else radiance x disc."""
    radiance = np.maximum(light_radiance(light), 0)
    half_angle = math.radians(min(max(light.angle, 0.0), 180.0) / 2)
    if not light.normalize and half_angle >= 1e-5:
        return radiance * math.pi * math.sin(min(half_angle, math.pi / 2)) ** 2
    return radiance


def latlong_directions(rows, cols, width, height, supersamples=1):
    """World directions in Mitsuba's envmap pixels (rows, cols) (u = atan2(x, -z) / 2pi, v = acos(y) / pi),
    shaped (pixels, s*s, 3) with s x s sub-pixel samples."""
    offsets = (np.arange(supersamples) + 0.5) / supersamples
    u = (np.asarray(cols)[:, None, None] + offsets[None, None, :]) / width
    v = (np.asarray(rows)[:, None, None] + offsets[None, :, None]) / height
    u, v = np.broadcast_arrays(u, v)
    phi, theta = 2 * math.pi * u.reshape(len(u), -1), math.pi * v.reshape(len(v), -1)
    return np.stack([np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)], axis=-1)


def environment(mi, lights):
    """One `envmap` (or `constant`) holding gi's dome lights and distant lights."""
    domes = [light for light in lights if light.kind == "dome"]
    suns = [light for light in lights if light.kind == "distant"]
    for light in domes:
        if light.texture_file:
            raise ConversionError(f"{light.name}: textured dome lights are not converted")
        if not light.visible_to_camera:
            raise ConversionError(f"{light.name}: a dome hidden from the camera is not converted")
    sky = sum((np.maximum(light_radiance(light), 0) for light in domes), np.zeros(3))
    if not suns:
        return {"type": "constant", "radiance": rgb(sky)} if domes else None
    width, height = SUN_MAP_WIDTH, SUN_MAP_WIDTH // 2
    image = np.tile(sky.astype(np.float32), (height, width, 1))
    pixel_solid_angle = (2 * math.pi / width) * (math.pi / height) * np.sin(math.pi * (np.arange(height) + 0.5) / height)
    for sun in suns:
        toward = column_major(sun.transform)[:3, :3] @ np.array([0.0, 0.0, 1.0])
        toward /= np.linalg.norm(toward)
        half_angle = math.radians(min(max(sun.angle, 0.0), 180.0) / 2)
        if half_angle < math.radians(0.05):
            raise ConversionError(f"{sun.name}: a distant light under 0.1 degrees cannot be painted into the map")
        # Pixels near the sun: those whose centre lies within the cone plus two pixels.
        rows, cols = np.indices((height, width)).reshape(2, -1)
        centres = latlong_directions(rows, cols, width, height)[:, 0, :]
        near = centres @ toward > math.cos(half_angle + 2 * 2 * math.pi / width)
        rows, cols, centres = rows[near], cols[near], centres[near]
        sub = latlong_directions(rows, cols, width, height, SUN_SUPERSAMPLES)
        coverage = (sub @ toward > math.cos(half_angle)).mean(axis=1)
        irradiance = sun_irradiance(sun)
        # Radiance so that sum(L * coverage * cos * pixel solid angle) is exactly gi's irradiance.
        cosines = centres @ toward
        painted = float(np.sum(coverage * cosines * pixel_solid_angle[rows]))
        image[rows, cols] += (coverage[:, None] * irradiance[None, :] / painted).astype(np.float32)
    return {"type": "envmap", "bitmap": mi.Bitmap(image)}


def camera_dict(mi, camera, resolution, spp, seed, framing=None):
    width, height = resolution
    # The conversion restates only the schema's default framing (an independent reading of
    # UsdGeomCamera, not gi's renderer/camera_framing.h); any other is refused.
    if framing is not None and tuple(framing) != ("expandAperture", 1.0):
        raise ConversionError(f"{camera.name}: aspectRatioConformPolicy and pixelAspectRatio {tuple(framing)} "
                              f"are not converted (only expandAperture with square pixels)")
    if camera.projection != "perspective":
        raise ConversionError(f"{camera.name}: {camera.projection} cameras are not converted")
    if camera.horizontal_aperture_offset or camera.vertical_aperture_offset:
        raise ConversionError(f"{camera.name}: aperture offsets are not converted")
    if camera.f_stop > 0 and camera.focus_distance > 0:
        raise ConversionError(f"{camera.name}: depth of field is not converted")
    ha, va = camera.horizontal_aperture, camera.vertical_aperture
    aspect = width / height
    ha = va * aspect if ha / va < aspect else ha   # expandAperture, as gi's Camera
    fov = math.degrees(2 * math.atan(ha / 2 / camera.focal_length))
    usd_to_mitsuba_camera = np.diag([-1.0, 1.0, -1.0, 1.0])  # looks down +Z with x to the left
    near, far = camera.clipping_range
    return {"type": "perspective", "fov": fov, "fov_axis": "x",
            "near_clip": float(max(near, 1e-4)), "far_clip": float(min(far, 1e7)),
            "to_world": mi.ScalarTransform4f(column_major(camera.transform) @ usd_to_mitsuba_camera),
            "film": {"type": "hdrfilm", "width": width, "height": height, "rfilter": {"type": "box"},
                     "pixel_format": "rgb", "component_format": "float32"},
            "sampler": {"type": "independent", "sample_count": spp, "seed": seed}}


GRAZING_NORMAL_COSINE = 0.1   # a vertex normal this close to the triangle's plane: flat shading in Mitsuba


def shading_normals_as_gi(positions, indices, normals, uvs):
    """gi drops zero-area triangles and turns an interpolated normal that faces away from the
    triangle's geometric normal to its side (scene.cpp). Mitsuba interpolates vertex normals as they
    are, and its shading frame turns NaN where a normal lies in the triangle's plane. So triangles
    with a vertex normal behind them get their own vertices, each normal turned to the geometric
    side (exactly gi's result when all three are behind: a mesh wound against its normals), and
    triangles with a normal within GRAZING_NORMAL_COSINE of their plane are shaded flat.
    Returns (positions, indices, normals, uvs, count of triangles shaded unlike gi)."""
    corners = positions[indices]
    geometric = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    area2 = np.einsum("ij,ij->i", geometric, geometric)
    keep = area2 > 0
    indices, geometric = indices[keep], geometric[keep] / np.sqrt(area2[keep])[:, None]
    if normals is None:
        return positions, indices, None, uvs, 0
    facing = np.einsum("tcj,tj->tc", normals[indices], geometric)   # (triangles, 3 corners)
    grazing = (np.abs(facing) < GRAZING_NORMAL_COSINE).any(axis=1)
    mixed = (facing < 0).any(axis=1) & (facing >= 0).any(axis=1)
    own = (facing < 0).any(axis=1) | grazing
    if not own.any():
        return positions, indices, normals, uvs, 0
    split = indices[own].reshape(-1)
    turned = normals[split] * np.where(facing[own].reshape(-1) < 0, -1.0, 1.0)[:, None]
    flat = np.repeat(grazing[own], 3)
    turned[flat] = np.repeat(geometric[own], 3, axis=0)[flat]
    new_indices = indices.copy()
    new_indices[own] = (len(positions) + np.arange(len(split))).reshape(-1, 3)
    return (np.concatenate([positions, positions[split]]), new_indices, np.concatenate([normals, turned]),
            None if uvs is None else np.concatenate([uvs, uvs[split]]), int((mixed | grazing).sum()))


def mitsuba_mesh(mi, shape, transform, bsdf, emitter, textured):
    """A world-space mi.Mesh of one of gi's triangle meshes. Texture coordinates only for textured
    materials: Mitsuba builds its shading frame's tangent from them, which turns NaN where a shading
    normal lies along it (untextured, the tangent is any one perpendicular to the normal)."""
    m = np.asarray(transform, np.float64)
    positions = shape.positions @ m[:3, :3] + m[3, :3]
    normals = None
    if shape.normals is not None:
        normals = shape.normals @ np.linalg.inv(m[:3, :3]).T   # row vectors: n' = n (M^-1)^T
        length = np.linalg.norm(normals, axis=1, keepdims=True)
        # gi sets zero normals to 0 (their weight drops out of the interpolation); they are rare
        # enough here that the triangle's geometric side decides (the split below).
        normals = np.where(length > 1e-6, normals / np.maximum(length, 1e-30), 0.0)
    positions, indices, normals, uvs, approximated = shading_normals_as_gi(
        positions, shape.indices.astype(np.int64), normals, shape.uvs if textured else None)
    props = mi.Properties()
    props["bsdf"] = bsdf
    if emitter is not None:
        props["emitter"] = emitter
    has_normals, has_uvs = normals is not None, uvs is not None
    mesh = mi.Mesh(shape.name, len(positions), len(indices), props, has_normals, has_uvs)
    params = mi.traverse(mesh)
    # The buffers' own types: mi.Float in a vectorised variant, a dynamic array in a scalar one.
    floats, uints = type(params["vertex_positions"]), type(params["faces"])
    params["vertex_positions"] = floats(positions.astype(np.float32).ravel())
    params["faces"] = uints(indices.astype(np.uint32).ravel())
    if has_normals:
        params["vertex_normals"] = floats(normals.astype(np.float32).ravel())
    if has_uvs:
        uvs = np.column_stack([uvs[:, 0], 1 - uvs[:, 1]])   # Mitsuba's v runs down the image
        params["vertex_texcoords"] = floats(uvs.astype(np.float32).ravel())
    params.update()
    return mesh, approximated


def emitter_of(mi, material, double_sided, name):
    if is_black(material.emissive_color):
        return None
    if double_sided:
        raise ConversionError(f"{name}: double-sided emission is not converted (Mitsuba's area emitters are one-sided)")
    return mi.load_dict({"type": "area", "radiance": rgb(material.emissive_color)})


def mitsuba_scene(recorded, resolution, spp=1, seed=0, rr_depth=3):
    """(mi.Scene of a RecordingScene, count of triangles shaded slightly unlike gi: see
    shading_normals_as_gi). Rendered by Mitsuba's `path` integrator (unbounded
    depth, Russian roulette from rr_depth, gi's `rouletteDepth` default 3)."""
    mi, _ = mitsuba()
    from gi import descriptors
    default_material = descriptors._MaterialDesc()
    bsdfs, scene, approximated_triangles = {}, {"type": "scene"}, 0
    scene["integrator"] = {"type": "path", "max_depth": -1, "rr_depth": rr_depth, "hide_emitters": False}
    scene["sensor"] = camera_dict(mi, recorded.camera, resolution, spp, seed, recorded.framing)
    for index, (shape, transform) in enumerate(world_shapes(recorded)):
        material = recorded.materials[shape.material] if shape.material >= 0 else default_material
        if shape.material not in bsdfs:
            bsdfs[shape.material] = mi.load_dict(bsdf_dict(mi, material))
        emitter = emitter_of(mi, material, shape.double_sided, shape.name)
        if shape.positions is not None:
            scene[f"shape{index}"], approximated = mitsuba_mesh(mi, shape, transform, bsdfs[shape.material], emitter,
                                                         texture_is_set(material.diffuse_color_texture))
            approximated_triangles += approximated
        else:
            sphere = {"type": "sphere", "bsdf": bsdfs[shape.material],
                      "to_world": mi.ScalarTransform4f(column_major(transform))
                      @ mi.ScalarTransform4f().translate(list(shape.center)).scale(shape.radius)}
            if emitter is not None:
                raise ConversionError(f"{shape.name}: emissive spheres are not converted")
            scene[f"shape{index}"] = sphere
    for index, light in enumerate(recorded.lights):
        if light.kind in ("rect", "disk", "sphere"):
            scene[f"light{index}"] = area_light_shape(mi, light)
        elif light.kind not in ("dome", "distant"):
            raise ConversionError(f"{light.name}: {light.kind} lights are not converted")
    env = environment(mi, recorded.lights)
    if env is not None:
        scene["environment"] = env
    return mi.load_dict(scene), approximated_triangles


# -- UsdPreviewSurface's specular workflow as a Mitsuba BSDF ---------------------------------------

_REGISTERED = []


def register_specular_workflow_bsdf(mi, dr):
    """Registers `usd_specular_workflow` once: UsdPreviewSurface's opaque lobes as gi defines them
    (renderer/bsdf.cpp, evalOpaque without clearcoat), written afresh in Dr.Jit:
        f = diffuse / pi * (1 - max F(cos_o)) + F(o.h) D(h) G(o, i) / (4 cos_o cos_i)
    F Schlick from f0 / f90, D GGX with alpha = roughness^2, G height-correlated Smith. Sampled as
    a mixture of cosine-weighted diffuse and GGX visible normals (any unbiased choice will do)."""
    if _REGISTERED:
        return

    def schlick(f0, f90, cos_theta):
        m = dr.clip(1 - cos_theta, 0, 1)
        m5 = dr.square(dr.square(m)) * m
        return f0 + (f90 - f0) * m5

    class SpecularWorkflow(mi.BSDF):
        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            self.diffuse = props["diffuse"]   # a texture, or a colour (an `rgb` value)
            self.f0 = mi.Color3f(props["f0"])
            self.f90 = props.get("f90", 1.0)
            self.alpha = max(props.get("roughness", 0.5) ** 2, 1e-4)
            if self.alpha < SMOOTH_ALPHA:
                raise ConversionError("usd_specular_workflow: smooth (roughness < 0.032) specular is not converted")
            self.distribution = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, self.alpha, True)
            reflection = mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.FrontSide
            glossy = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
            self.m_components = [reflection, glossy]
            self.m_flags = reflection | glossy

        def lambda_smith(self, cos_theta):
            c2 = dr.square(cos_theta)
            tan2 = dr.maximum(1 - c2, 0) / dr.maximum(c2, 1e-12)
            return (dr.sqrt(1 + self.alpha * self.alpha * tan2) - 1) / 2

        def ggx_d(self, cos_h):
            a2 = self.alpha * self.alpha
            d = dr.square(cos_h) * (a2 - 1) + 1
            return dr.select(cos_h > 0, a2 / (dr.pi * dr.square(d)), 0)

        def spectra(self, si, active):
            albedo = self.diffuse.eval(si, active) if isinstance(self.diffuse, mi.Texture) else mi.Color3f(self.diffuse)
            return self.f0, dr.minimum(albedo, 1)

        def specular_probability(self, si, f0, albedo):
            fs = schlick(f0, self.f90, mi.Frame3f.cos_theta(si.wi))
            lum = lambda c: 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]  # noqa: E731
            specular = lum(fs)
            diffuse = lum(albedo) * (1 - dr.max(fs))
            return dr.select(specular + diffuse > 0, specular / (specular + diffuse), 1.0)

        def eval_all(self, si, wo, active):
            wi = si.wi
            cos_i, cos_o = mi.Frame3f.cos_theta(wi), mi.Frame3f.cos_theta(wo)
            active &= (cos_i > 0) & (cos_o > 0)
            f0, albedo = self.spectra(si, active)
            h = dr.normalize(wi + wo)
            fs = schlick(f0, self.f90, dr.dot(wi, h))
            g = 1 / (1 + self.lambda_smith(cos_i) + self.lambda_smith(cos_o))
            specular = fs * self.ggx_d(mi.Frame3f.cos_theta(h)) * g / (4 * cos_i * cos_o)
            diffuse = albedo * dr.inv_pi * (1 - dr.max(schlick(f0, self.f90, cos_i)))
            value = (diffuse + specular) * cos_o
            return dr.select(active, value, 0), f0, albedo

        def pdf_all(self, si, wo, f0, albedo, active):
            cos_i, cos_o = mi.Frame3f.cos_theta(si.wi), mi.Frame3f.cos_theta(wo)
            active &= (cos_i > 0) & (cos_o > 0)
            p_specular = self.specular_probability(si, f0, albedo)
            h = dr.normalize(si.wi + wo)
            pdf_specular = self.distribution.pdf(si.wi, h) / (4 * dr.abs_dot(wo, h))
            pdf_diffuse = mi.warp.square_to_cosine_hemisphere_pdf(wo)
            return dr.select(active, p_specular * pdf_specular + (1 - p_specular) * pdf_diffuse, 0)

        def sample(self, ctx, si, sample1, sample2, active):
            f0, albedo = self.spectra(si, active)
            p_specular = self.specular_probability(si, f0, albedo)
            choose_specular = sample1 < p_specular
            m, _ = self.distribution.sample(si.wi, sample2)
            wo = dr.select(choose_specular, mi.reflect(si.wi, m), mi.warp.square_to_cosine_hemisphere(sample2))
            bs = mi.BSDFSample3f()
            bs.wo = wo
            bs.eta = 1.0
            bs.sampled_component = dr.select(choose_specular, mi.UInt32(1), mi.UInt32(0))
            bs.sampled_type = dr.select(choose_specular, mi.UInt32(+mi.BSDFFlags.GlossyReflection),
                                        mi.UInt32(+mi.BSDFFlags.DiffuseReflection))
            value, _, _ = self.eval_all(si, wo, active)
            bs.pdf = self.pdf_all(si, wo, f0, albedo, active)
            ok = active & (bs.pdf > 0) & (mi.Frame3f.cos_theta(si.wi) > 0)
            return bs, dr.select(ok, value / dr.select(ok, bs.pdf, 1), 0)

        def eval(self, ctx, si, wo, active):
            return self.eval_all(si, wo, active)[0]

        def pdf(self, ctx, si, wo, active):
            f0, albedo = self.spectra(si, active)
            return self.pdf_all(si, wo, f0, albedo, active)

        def eval_pdf(self, ctx, si, wo, active):
            value, f0, albedo = self.eval_all(si, wo, active)
            return value, self.pdf_all(si, wo, f0, albedo, active)

        def traverse(self, callback):
            pass

        def to_string(self):
            return f"usd_specular_workflow[alpha={self.alpha}, f90={self.f90}]"

    mi.register_bsdf("usd_specular_workflow", lambda props: SpecularWorkflow(props))
    _REGISTERED.append(True)


def with_converted_normals(recorded):
    """A copy of `recorded` whose meshes carry the vertex normals the Mitsuba scene gets
    (shading_normals_as_gi): fed to gi, it tells a difference of normal conventions from one of
    light transport."""
    import copy
    out = copy.copy(recorded)
    out.shapes = []
    for shape in recorded.shapes:
        shape = copy.copy(shape)
        if shape.normals is not None:
            length = np.linalg.norm(shape.normals, axis=1, keepdims=True)
            normals = np.where(length > 1e-6, shape.normals / np.maximum(length, 1e-30), 0.0)
            shape.positions, indices, shape.normals, shape.uvs, _ = shading_normals_as_gi(
                shape.positions, shape.indices.astype(np.int64), normals, shape.uvs)
            shape.indices = indices.astype(np.uint32)
        out.shapes.append(shape)
    return out


def gi_scene(recorded):
    """A committed gi._core.Scene holding what `recorded` holds."""
    from gi.descriptors import new_scene
    scene = new_scene()
    for material in recorded.materials:
        scene.add_material(material)
    for name in recorded.prototypes:
        scene.add_prototype(name)

    def array(values, dtype):
        return None if values is None else np.ascontiguousarray(values, dtype)
    for shape in recorded.shapes:
        if shape.positions is None:
            scene.add_sphere(shape.name, shape.center, shape.radius, shape.material, shape.transform, shape.prototype)
        else:
            scene.add_mesh(shape.name, array(shape.positions, np.float32), array(shape.indices, np.uint32),
                           array(shape.normals, np.float32), array(shape.uvs, np.float32), shape.material,
                           shape.transform, shape.double_sided, shape.prototype)
    for prototype, transform in recorded.instances:
        scene.add_instance(prototype, transform)
    for light in recorded.lights:
        scene.add_light(light)
    scene.set_camera(recorded.camera)
    scene.commit()
    return scene


def render(scene, spp, seed, threads):
    """(linear RGB float32 image, seconds) of one Mitsuba render; the scene's own sampler is reseeded."""
    import time
    mi, dr = mitsuba()
    dr.set_thread_count(threads)
    start = time.perf_counter()
    image = mi.render(scene, spp=spp, seed=seed)
    array = np.array(image, dtype=np.float32)   # forces evaluation of the kernel
    return array, time.perf_counter() - start
