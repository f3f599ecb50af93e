"""Type stubs for gi._core, the nanobind module over the C++ renderer (renderer/).

Conventions
- Matrices are 4x4 float64 arrays in USD's convention: row vectors, p' = p @ M, translation in
  the last row (exactly what Gf.Matrix4d holds; `np.array(gf_matrix)` gives it).
- Colors are linear RGB (Rec.709 primaries) float tuples.
- Every `name` is the USD prim path the object came from; the renderer uses it in warnings.
"""
from typing import Callable, Optional, Sequence, Union
import numpy as np
import numpy.typing as npt

class TextureDesc:
    """A UsdUVTexture reading a file, with its UsdPrimvarReader_float2 / UsdTransform2d."""
    file: str                      # resolved absolute path ('' = none)
    wrap_s: str                    # 'repeat' | 'mirror' | 'clamp' | 'black' | 'useMetadata'
    wrap_t: str
    scale: tuple[float, float, float, float]
    bias: tuple[float, float, float, float]
    fallback: tuple[float, float, float, float]
    channel: str                   # 'rgb' | 'r' | 'g' | 'b' | 'a'  (which output is connected)
    source_color_space: str        # 'auto' | 'raw' | 'sRGB'
    st_rotation: float             # UsdTransform2d, degrees
    st_scale: tuple[float, float]
    st_translation: tuple[float, float]
    def __init__(self) -> None: ...

class MaterialDesc:
    """UsdPreviewSurface inputs. A `*_texture` with an empty file means 'use the constant'."""
    name: str
    diffuse_color: tuple[float, float, float]
    emissive_color: tuple[float, float, float]
    use_specular_workflow: bool
    specular_color: tuple[float, float, float]
    metallic: float
    roughness: float
    clearcoat: float
    clearcoat_roughness: float
    opacity: float
    opacity_mode: str              # 'transparent' | 'presence'
    opacity_threshold: float
    ior: float
    diffuse_color_texture: TextureDesc
    emissive_color_texture: TextureDesc
    specular_color_texture: TextureDesc
    metallic_texture: TextureDesc
    roughness_texture: TextureDesc
    opacity_texture: TextureDesc
    normal_texture: TextureDesc
    def __init__(self) -> None: ...

class LightDesc:
    """A UsdLux light. `kind` is the schema: 'rect' | 'disk' | 'sphere' | 'cylinder' | 'distant' | 'dome'."""
    name: str
    kind: str
    color: tuple[float, float, float]
    intensity: float
    exposure: float
    normalize: bool
    width: float                   # rect
    height: float                  # rect
    radius: float                  # disk, sphere, cylinder
    length: float                  # cylinder (along local X)
    angle: float                   # distant: angular diameter in degrees
    texture_file: str              # dome lat-long map or rect light texture ('' = none)
    transform: npt.NDArray[np.float64]   # 4x4, USD convention, at the frame
    # (steps, 4, 4) over the shutter (even steps, open to close) when it moves, else None; area
    # lights (rect, disk, sphere, cylinder) are blurred, the others warn and stay at `transform`.
    motion_transforms: Optional[npt.NDArray[np.float64]]
    visible_to_camera: bool
    def __init__(self) -> None: ...

class CameraDesc:
    """A UsdGeomCamera. Lengths in the schema's units (focal length / apertures in tenths of a scene unit)."""
    name: str
    projection: str                # 'perspective' | 'orthographic'
    focal_length: float
    horizontal_aperture: float
    vertical_aperture: float
    horizontal_aperture_offset: float
    vertical_aperture_offset: float
    f_stop: float                  # 0 = pinhole
    focus_distance: float
    clipping_range: tuple[float, float]
    shutter_open: float            # frames relative to the rendered time; close > open: motion blur,
    shutter_close: float           # each camera ray at a time in [open, close] (close < open: warned)
    transform: npt.NDArray[np.float64]   # 4x4 camera-to-world, USD convention (camera looks down -Z)
    motion_transforms: Optional[npt.NDArray[np.float64]]  # (S, 4, 4) over the shutter when it moves, else None
    def __init__(self) -> None: ...

class Scene:
    """Geometry, materials, lights and camera. Build it, then render it (it is committed on first render)."""
    def __init__(self) -> None: ...
    def add_material(self, material: MaterialDesc) -> int: ...
    def add_prototype(self, name: str) -> int:
        """A group of meshes/spheres that instances refer to (a point-instancer prototype or an
        instanceable prim's master). Returns its id."""
    def add_mesh(self, name: str,
                 positions: npt.NDArray[np.float32],        # (N, 3)
                 indices: npt.NDArray[np.uint32],           # (M, 3) triangles
                 normals: Optional[npt.NDArray[np.float32]] = None,   # (N, 3) per vertex, or None
                 uvs: Optional[npt.NDArray[np.float32]] = None,       # (N, 2) per vertex, or None
                 material: int = -1,                       # -1 = default grey diffuse
                 transform: Optional[npt.NDArray[np.float64]] = None, # 4x4 USD convention
                 double_sided: bool = True,
                 prototype: int = -1,
                 motion_points: Optional[npt.NDArray[np.float32]] = None,      # (S, N, 3)
                 motion_transforms: Optional[npt.NDArray[np.float64]] = None,  # (S, 4, 4)
                 ) -> int:
        """Adds a triangle mesh (in `prototype` if >= 0). Face-varying data must be de-indexed by the
        caller. Bad data (NaN points, out-of-range indices, degenerate triangles) is repaired or
        dropped with a warning naming `name`; returns -1 (with a warning) if nothing usable remains.
        Motion blur: the points (deformation) and/or the transform at S >= 2 evenly spaced times over
        the camera's shutter, the first at shutter open; all steps equal: static."""
    def add_sphere(self, name: str, center: Sequence[float], radius: float, material: int = -1,
                   transform: Optional[npt.NDArray[np.float64]] = None, prototype: int = -1,
                   motion_transforms: Optional[npt.NDArray[np.float64]] = None) -> int:
        """An exact sphere (Embree sphere geometry). Non-uniform transforms are handled by instancing."""
    def add_instance(self, prototype: int, transform: npt.NDArray[np.float64], name: str = "",
                     motion_transforms: Optional[npt.NDArray[np.float64]] = None) -> int: ...
    def add_light(self, light: LightDesc) -> int: ...
    def set_camera(self, camera: CameraDesc) -> None: ...
    def commit(self) -> None:
        """Builds the BVH and lights (render() does it if needed). The scene is read-only afterwards."""
    def warnings(self) -> list[str]:
        """Every warning issued while building and committing, each naming its prim."""
    def stats(self) -> dict: ...   # triangles, spheres, instances, prototypes, lights, emissive_triangles,
                                   # textures, texture_bytes, build_seconds, committed, specular_surfaces,
                                   # moving_shapes, moving_instances (Embree motion geometry),
                                   # moving_lights (area lights moving during the shutter)

class RenderSettings:
    width: int
    height: int
    spp: int                       # camera samples per pixel
    integrator: str                # a name from integrators()
    params: dict                   # integrator parameter name (camelCase) -> int | float | bool
    preset: str                    # a name from presets() under params ('' = defaults); unknown: ValueError
    seed: int
    threads: int                   # 0 = all
    time_limit: float              # seconds for the whole call (scene commit and preprocessing included), 0 = none
    filter: str                    # pixel reconstruction filter: 'box' (default) | 'gaussian'
    data_window: tuple[int, int, int, int]  # (x0, y0, x1, y1): render only pixels [x0, x1) x [y0, y1), equal bit
                                   # for bit to the whole image's there; (0, 0, 0, 0) = the whole image
    aspect_ratio_conform_policy: str  # UsdRenderSettings' token: 'expandAperture' (default) | 'cropAperture' |
                                   # 'adjustApertureWidth' | 'adjustApertureHeight' | 'adjustPixelAspectRatio';
                                   # another: ValueError
    pixel_aspect_ratio: float      # a pixel's width over its height (default 1)
    def __init__(self) -> None: ...

class RenderResult:
    color: npt.NDArray[np.float32]     # (H, W, 3) linear RGB, top row first
    depth: npt.NDArray[np.float32]     # (H, W) camera-space distance, inf where nothing was hit
    normal: npt.NDArray[np.float32]    # (H, W, 3) world-space shading normal
    albedo: npt.NDArray[np.float32]    # (H, W, 3)
    prim_id: npt.NDArray[np.int32]     # (H, W) the scene's shape id nearest the pixel centre, -1 for none
    instance_id: npt.NDArray[np.int32] # (H, W) its instance id, -1 for none
    data_window: tuple[int, int, int, int]  # (x0, y0, x1, y1) of the pixels rendered (outside: empty)
    spp: int                           # samples per pixel of the complete passes
    stats: dict                        # seconds, preprocess_seconds, render_seconds, rays, rays_per_second,
                                       # camera_samples, samples_per_second, non_finite_samples, clamped_samples,
                                       # depth_capped_paths, peak_memory_bytes, spp, partial_pass_pixels and
                                       # partial_pass_samples (the last pass the time limit cut: the pixels
                                       # that have its samples too), preprocess_scaled_down (times
                                       # preprocessing did less than asked to keep the time limit),
                                       # sample_thread_seconds (the passes' tiles, summed over threads),
                                       # pass_setup_seconds (wall, the passes' setup), + the integrator's
                                       # own statistics; auto_pilot_seconds with "auto"
    integrator: str                    # the integrator that rendered ("auto" resolves to one)
    auto_summary: str                  # with "auto": the choice and each technique's predicted RMSE and spp; else ""

def presets() -> list[dict]:
    """[{'name', 'description', 'params': {integrator: {parameter: value}}}] (e.g. 'thesis')"""

def auto_candidates() -> list[str]:
    """The techniques integrator 'auto' chooses among (its pilots render them in this order)."""

def integrators() -> list[dict]:
    """[{'name', 'description', 'params': [{'name', 'type' ('int'|'float'|'bool'), 'default', 'min', 'max', 'description'}]}]"""

def render(scene: Scene, settings: RenderSettings,
           progress: Optional[Callable[[float], None]] = None,
           camera: Optional[CameraDesc] = None) -> RenderResult:
    """Renders with all threads; progress(fraction_done) is called from the calling thread every
    50 ms and once with 1.0 at the end. camera: used instead of the scene's (a committed scene
    renders again from another view, e.g. each frame of a camera move). Releases the GIL while rendering. KeyboardInterrupt cancels.
    Raises ValueError for an unknown integrator or resolution."""

def write_exr(path: str, result: RenderResult, metadata: dict[str, str] = {},
              color: Optional[npt.NDArray[np.float32]] = None,
              layers: dict[str, npt.NDArray[np.float32]] = {}) -> None:
    """Linear half/float EXR with R,G,B plus depth (Z; the largest finite float where nothing was hit, so the file holds no Inf), normal (N.x..), albedo (albedo.r..) layers; metadata as string attributes.
    `color` (H, W, 3) replaces the render's colour as R,G,B (e.g. the denoised one); each of `layers`
    (name -> (H, W, 3)) is written as name.R, name.G, name.B (e.g. noisy.R for the raw colour).
    Only the result's data window is written (as the EXR's data window within the whole image)."""

def write_channels_exr(path: str, pixels: npt.NDArray[np.float32], channels: list[str],
                       metadata: dict[str, str] = {},
                       data_window: Optional[tuple[int, int, int, int]] = None,
                       half: list[bool] = []) -> None:
    """An EXR from an (H, W, C) array and C channel names (e.g. 'N.X'). data_window (x, y, full
    width, full height): the array is that part of a larger image. half: per channel, stored as
    16-bit half floats (else 32-bit floats)."""

def write_rgb_exr(path: str, color: npt.NDArray[np.float32], metadata: dict[str, str] = {}) -> None:
    """A plain linear R,G,B EXR from an (H, W, 3) array."""

def write_png(path: str, color: npt.NDArray[np.float32], display: str = "", view: str = "",
              exposure: float = 0.0, config: str = "") -> None:
    """Display-referred 8-bit PNG through an OpenColorIO display/view (config: explicit, else
    $OCIO, else the config shipped in gi/ocio/). Empty display/view = the config's defaults."""

def data_window_pixels(ndc: tuple[float, float, float, float], width: int, height: int
                       ) -> tuple[tuple[int, int, int, int], str]:
    """A dataWindowNDC (xmin, ymin, xmax, ymax; y up) as the pixels (x0, y0, x1, y1), row 0 at the
    top, whose centres it holds, clipped to the image; and '' or a warning sentence
    (renderer/pixel_window.h, hdGi's rule too)."""

def read_image(path: str) -> tuple[npt.NDArray[np.float32], dict]:
    """(H, W, C) float pixels of the data window and the file's metadata, through OpenImageIO; the
    metadata also has 'channels', 'channel_formats' ('half', 'float', ...), 'data_window' (x, y, W, H) and 'display_window' (full W, full H)."""

def display_transform(color: npt.NDArray[np.float32], display: str = "", view: str = "",
                      exposure: float = 0.0, config: str = "") -> npt.NDArray[np.float32]:
    """The OCIO display transform as float (H, W, 3) in [0, 1]."""

def embree_ray_benchmark(scene: Scene, rays: int, seed: int = 0, threads: int = 0) -> dict:
    """Embree alone: `rays` incoherent closest-hit rays in the committed scene -> {rays, hits, seconds, rays_per_second}."""

def embree_replay_render_rays(scene: Scene, settings: RenderSettings, order: str = "render") -> dict:
    """Renders once timed, once recording its rays, then casts those rays through Embree alone, in
    `order`: 'render' (one by one, as rendered), 'wavefront' (waves of paths, each step's rays
    together) or 'wavefront-packets8' (the same as 8-wide packets) -> {render_rays, render_seconds,
    render_cpu_seconds, replay_rays, replay_seconds, replay_cpu_seconds}."""

def peak_memory_bytes() -> int: ...

class DenoiserUnavailable(RuntimeError):
    """No Open Image Denoise 2.x could be loaded; the message lists where it looked and what to install."""

class Denoiser:
    """Intel Open Image Denoise 2.x's "RT" filter on its CPU device, loaded at run time (renderer/denoiser.h).
    Not thread-safe: it keeps its filters between calls of one image size."""
    version: str        # of the loaded OIDN, e.g. "2.5.1"
    library_path: str   # the libOpenImageDenoise file loaded
    def __init__(self, library_folders: Sequence[str] = (), threads: int = 0) -> None:
        """Looks in $GI_OIDN_LIBRARY (alone, when set), else `library_folders`, the copy found when the
        renderer was built, the system loader's path. Raises DenoiserUnavailable."""
    def denoise(self, color: npt.NDArray[np.float32], albedo: npt.NDArray[np.float32],
                normal: npt.NDArray[np.float32], prefilter_aux: bool = True) -> npt.NDArray[np.float32]:
        """The denoised (H, W, 3) linear colour, guided by the albedo and normal AOVs (H, W, 3);
        prefilter_aux denoises those first and treats them as clean (OIDN's final-frame set-up).
        Releases the GIL. Raises RuntimeError if OIDN fails or returns a non-finite value."""

def read_obj(path: str) -> dict:
    """A Wavefront OBJ (and its MTL) through tinyobjloader: {meshes: one per (group, material) in file
    order, each {name, material, points (P,3), face_vertex_counts, face_vertex_indices, normals (N,3),
    normal_indices, source_has_normals, uvs (T,2), uv_indices}, materials: [{name, Ka, Kd, Ks, Ke, Tf,
    Ns, Ni, d, illum, Pr, Pm, maps: {key: {file, scale, offset, bump_multiplier}}}], faces,
    repaired_normals, degenerate_faces, warnings}. Unusable normals are replaced by face normals.
    Raises RuntimeError naming the file."""

def read_gltf(path: str) -> dict:
    """A glTF 2.0 file (.gltf or .glb) through tinygltf: {meshes: [{name, primitives: [{points,
    face_vertex_indices (triangles), normals, source_has_normals, uvs (t flipped up), material}]}],
    nodes: [{name, mesh, children, matrix, translation, rotation, scale}], roots, materials
    (metallic-roughness), images: [{name, mime_type, uri (percent-encoded) or bytes}], generator,
    copyright, repaired_normals, warnings}. Raises RuntimeError naming the file."""

class MeshPrimvar:
    """A mesh primvar for tessellate_mesh: (N, width) float32 values, UsdGeom's interpolation token and
    optional int32 indices (an indexed primvar's)."""
    name: str
    interpolation: str
    def __init__(self, name: str, values: npt.NDArray[np.float32], interpolation: str,
                 indices: Optional[npt.NDArray[np.int32]] = None) -> None: ...

class SubdivisionRules:
    """UsdGeomMesh's subdivision attributes, as its tokens (an unknown token is a warning and the
    attribute's fallback)."""
    scheme: str                               # catmullClark (default), loop, bilinear, none
    interpolate_boundary: str                 # edgeAndCorner (default), edgeOnly, none
    face_varying_linear_interpolation: str    # cornersPlus1 (default), none, cornersOnly, cornersPlus2, boundaries, all
    triangle_subdivision_rule: str            # catmullClark (default), smooth
    crease_indices: list[int]
    crease_lengths: list[int]
    crease_sharpnesses: list[float]           # one per crease or one per crease edge
    corner_indices: list[int]
    corner_sharpnesses: list[float]
    def __init__(self) -> None: ...

def tessellate_mesh(points: npt.NDArray[np.float32], face_vertex_counts: npt.NDArray[np.int32],
                    face_vertex_indices: npt.NDArray[np.int32], hole_indices: Optional[npt.NDArray[np.int32]] = None,
                    orientation: str = "rightHanded", normals: Optional[MeshPrimvar] = None,
                    uvs: Optional[MeshPrimvar] = None, subdivision: Optional[SubdivisionRules] = None,
                    refine_level: int = 0, piece_of_face: Optional[npt.NDArray[np.int32]] = None,
                    pieces: int = 1) -> dict:
    """A UsdGeomMesh's arrays as the renderer's triangles, by the rules the Hydra delegate uses too
    (renderer/mesh_description.h): usable faces, holes, orientation, primvar interpolations,
    OpenSubdiv refinement `refine_level` times (subdivision None: a polygon mesh). Returns
    {'pieces': [one dict per piece of piece_of_face (None: one piece): 'positions' (N, 3) float32,
    'indices' (M, 3) uint32 or None when empty, 'normals' / 'uvs' per vertex or None, 'faces' (M,)
    int64 the authored face of each triangle], 'warnings': [str], 'refined': bool}."""

def assign_subset_faces(face_count: int, subsets: Sequence[tuple[str, Optional[npt.NDArray[np.int32]]]],
                        family_type: str, mesh_path: str) -> dict:
    """Which materialBind face subset owns each face (renderer/mesh_pieces.h, the Hydra delegate's rule
    too): valid indices once each, a face claimed by several subsets going to the first, a
    'partition' family's faces in none reported. Returns {'piece_of_face': int32 (face_count,) (0:
    the mesh's own, i + 1: subsets[i]; None when face_count is 0), 'owns_faces': [bool] per subset,
    'warnings': [(prim path, message)]}."""

# The shading rules shared with the Hydra delegate (renderer/usd_shading.h).
class ShaderAsset:
    """An asset-valued shader input: the path as authored and the file it resolves to ('' = none)."""
    authored: str
    resolved: str
    def __init__(self, authored: str = "", resolved: str = "") -> None: ...

class ShaderNode:
    """A shader in a ShaderNetwork (renderer/shader_network.h): its id and its authored inputs."""
    id: str
    def __init__(self, id: str = "") -> None: ...
    def set(self, input: str, value: Union[float, int, bool, str, tuple, list, ShaderAsset]) -> None:
        """An authored constant on `input` (without 'inputs:'): a number, 2 to 4 numbers, a str or an asset."""
    def connect(self, input: str, node: str, output: str) -> None:
        """`input` driven by output `output` of the node at path `node`."""

class ShaderNetwork:
    """A material's shaders by prim path, as the stage authors them."""
    def __init__(self) -> None: ...
    def add(self, path: str, node: ShaderNode) -> None: ...
    def __contains__(self, path: str) -> bool: ...

def resolve_preview_surface(material_path: str, network: ShaderNetwork, surface: str,
                            warn: Callable[[str, str], None]
                            ) -> Optional[tuple[MaterialDesc, list[str], list[tuple[str, str]]]]:
    """The material whose surface output node `surface` ('' for none) drives, by the rules hdGi
    shares (renderer/preview_surface.h): (MaterialDesc, the varnames its primvar readers read, the
    texture files it names as (authored, resolved)); None after warn(material_path, message) when
    it is not a UsdPreviewSurface. Each warning names the node and input, once."""

def framing_camera(center: tuple[float, float, float], size: tuple[float, float, float], z_up: bool) -> CameraDesc:
    """The camera that frames a bounding box (its centre and size) when the stage has none:
    usdrecord's free camera (renderer/camera_framing.h)."""

def display_color_material(prim: str, display_color: Optional[tuple[float, float, float]] = None) -> MaterialDesc:
    """The material of a gprim with no usable material: UsdPreviewSurface defaults, diffuse colour
    = its displayColor when it has one."""

def uv_primvar_of(reader_varnames: list[str], mesh_primvars: list[str]) -> str:
    """The first UsdPrimvarReader_float2 varname the mesh has as a primvar, else '' (no texture
    coordinates)."""
