"""UsdGeom prims to the arrays gi._core.Scene.add_mesh takes: polygon and subdivision meshes (read
here, tessellated by the renderer's rules through gi._core.tessellate_mesh) and tessellations of
the implicit prims the renderer has no exact shape for (cube, cylinder, cone, capsule, plane).

`warn(message)` reports a problem; the caller adds the file and prim path."""
from dataclasses import dataclass
from typing import Optional

import numpy as np
from pxr import UsdGeom

IMPLICIT_TYPES = ("Cube", "Cylinder", "Cylinder_1", "Cone", "Capsule", "Capsule_1", "Plane")


@dataclass
class Triangles:
    positions: np.ndarray             # (N, 3) float32
    indices: np.ndarray               # (M, 3) uint32
    normals: Optional[np.ndarray] = None   # (N, 3) float32
    uvs: Optional[np.ndarray] = None       # (N, 2) float32
    faces: Optional[np.ndarray] = None     # (M,) int64: the authored face each triangle came from

    def contiguous(self):
        """nanobind takes C-contiguous arrays of exactly these dtypes."""
        def fix(a, dtype):
            return None if a is None else np.ascontiguousarray(a, dtype=dtype)
        return Triangles(fix(self.positions, np.float32), fix(self.indices, np.uint32),
                         fix(self.normals, np.float32), fix(self.uvs, np.float32), fix(self.faces, np.int64))


# -- polygon and subdivision meshes -------------------------------------------------------------
# The rules (usable faces, holes, orientation, primvar interpolation, OpenSubdiv refinement) are the
# renderer's, shared with the Hydra delegate: gi._core.tessellate_mesh (renderer/mesh_description.h).
# Here the mesh's attributes are only read.

def mesh_primvar(primvar, time, name):
    """A UsdGeom primvar's authored values, interpolation and indices as a gi._core.MeshPrimvar
    (None when it has no values)."""
    return primvar_arrays(primvar.Get(time), primvar.GetInterpolation(),
                          primvar.GetIndices(time) if primvar.IsIndexed() else None, name)


def primvar_arrays(values, interpolation, indices, name):
    from ._core import MeshPrimvar
    if values is None or len(values) == 0:
        return None
    values = np.asarray(values, dtype=np.float32)
    values = np.ascontiguousarray(values.reshape(len(values), -1))
    indices = None if indices is None else np.ascontiguousarray(indices, dtype=np.int32)
    return MeshPrimvar(name, values, str(interpolation), indices)


def mesh_normals(mesh, time):
    """primvars:normals if authored (it wins over the normals attribute), else normals."""
    primvar = UsdGeom.PrimvarsAPI(mesh).GetPrimvar("normals")
    if primvar and primvar.HasAuthoredValue():
        return mesh_primvar(primvar, time, "primvars:normals")
    attribute = mesh.GetNormalsAttr()
    if attribute.HasAuthoredValue():
        return primvar_arrays(attribute.Get(time), mesh.GetNormalsInterpolation(), None, "normals")
    return None


def uv_primvar(mesh, reader_varnames=()):
    """The texture-coordinate primvar: the first of the materials' UsdPrimvarReader_float2 varnames
    that the mesh has (gi._core.uv_primvar_of, the rule hdGi follows), else None."""
    from ._core import uv_primvar_of
    api = UsdGeom.PrimvarsAPI(mesh)
    authored = [p.GetPrimvarName() for p in api.GetPrimvarsWithAuthoredValues()]
    name = uv_primvar_of(list(reader_varnames), [str(n) for n in authored])
    return api.GetPrimvar(name) if name else None


def mesh_uvs(mesh, time, reader_varnames=()):
    primvar = uv_primvar(mesh, reader_varnames)
    return None if primvar is None else mesh_primvar(primvar, time, f"primvars:{primvar.GetPrimvarName()}")


def int_array(attribute, time):
    return np.ascontiguousarray(attribute.Get(time) or [], dtype=np.int32).reshape(-1)


def subdivision_rules(mesh, time):
    """The mesh's subdivision scheme and tags as a gi._core.SubdivisionRules."""
    from ._core import SubdivisionRules
    rules = SubdivisionRules()
    rules.scheme = str(mesh.GetSubdivisionSchemeAttr().Get(time))
    rules.interpolate_boundary = str(mesh.GetInterpolateBoundaryAttr().Get(time))
    rules.face_varying_linear_interpolation = str(mesh.GetFaceVaryingLinearInterpolationAttr().Get(time))
    rules.triangle_subdivision_rule = str(mesh.GetTriangleSubdivisionRuleAttr().Get(time))
    rules.crease_indices = int_array(mesh.GetCreaseIndicesAttr(), time).tolist()
    rules.crease_lengths = int_array(mesh.GetCreaseLengthsAttr(), time).tolist()
    rules.crease_sharpnesses = [float(v) for v in mesh.GetCreaseSharpnessesAttr().Get(time) or []]
    rules.corner_indices = int_array(mesh.GetCornerIndicesAttr(), time).tolist()
    rules.corner_sharpnesses = [float(v) for v in mesh.GetCornerSharpnessesAttr().Get(time) or []]
    return rules


def mesh_triangles(mesh: UsdGeom.Mesh, time, warn, uv_names=(), refine_level=0, piece_of_face=None, pieces=1):
    """The mesh's triangles (refined `refine_level` times if it is a subdivision surface) in `pieces`
    pieces by authored face (piece_of_face: see assign_subset_faces; None: one piece); an empty
    piece is None, and the whole is None if no triangle remains (a warning says why when something
    was wrong). Each piece's `faces` holds its triangles' authored faces."""
    points = np.asarray(mesh.GetPointsAttr().Get(time) or [], dtype=np.float32).reshape(-1, 3)
    counts = int_array(mesh.GetFaceVertexCountsAttr(), time)
    try:
        from ._core import tessellate_mesh
    except ImportError:  # no compiled renderer (gi inspect): the mesh is counted, not tessellated
        return [Triangles(points, np.zeros((0, 3), np.uint32), faces=np.zeros(0, np.int64))]
    out = tessellate_mesh(np.ascontiguousarray(points), counts, int_array(mesh.GetFaceVertexIndicesAttr(), time),
                          int_array(mesh.GetHoleIndicesAttr(), time), str(mesh.GetOrientationAttr().Get(time)),
                          mesh_normals(mesh, time), mesh_uvs(mesh, time, uv_names), subdivision_rules(mesh, time),
                          refine_level, piece_of_face, pieces)
    for message in out["warnings"]:
        warn(message)
    pieces = [None if p["indices"] is None else
              Triangles(p["positions"], p["indices"], p["normals"], p["uvs"], p["faces"]).contiguous()
              for p in out["pieces"]]
    return None if all(p is None for p in pieces) else pieces


# -- implicit prims ------------------------------------------------------------------------------

def axis_frame(axis):
    """Rows mapping a shape built around +Z onto `axis` (row vectors: p @ frame); determinant +1,
    so windings stay outward-facing."""
    if axis == "X":
        return np.array([[0, 0, -1], [0, 1, 0], [1, 0, 0]], np.float64)
    if axis == "Y":
        return np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], np.float64)
    return np.eye(3)


def revolve(profile, segments):
    """A closed surface of revolution about +Z from a bottom-to-top (radius, z) profile."""
    angles = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    rings = [np.stack([r * np.cos(angles), r * np.sin(angles), np.full(segments, z)], axis=1)
             for r, z in profile]
    positions = np.concatenate(rings)
    ring, step = np.meshgrid(np.arange(len(profile) - 1), np.arange(segments), indexing="ij")
    a = (ring * segments + step).reshape(-1)
    b = (ring * segments + (step + 1) % segments).reshape(-1)
    c, d = a + segments, b + segments
    triangles = np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)])
    # Rings of radius 0 (poles, apexes) make zero-area triangles: leave them out.
    p = positions[triangles]
    area = np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    return positions, triangles[area > 1e-12]


def cube_triangles(size):
    s = size / 2
    corners = np.array([[x, y, z] for x in (-s, s) for y in (-s, s) for z in (-s, s)], np.float64)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    triangles = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))])
    return corners, triangles


def plane_triangles(width, length, axis):
    w, l = width / 2, length / 2
    quad = np.array([[-w, -l, 0], [w, -l, 0], [w, l, 0], [-w, l, 0]], np.float64)
    return quad @ axis_frame(axis), np.array([[0, 1, 2], [0, 2, 3]])


def hemisphere_profile(radius, center_z, upper, rings=8):
    """(radius, z) from the equator to the pole (upper) or from the pole to the equator (lower)."""
    angles = np.linspace(0, np.pi / 2, rings + 1)
    cap = [(radius * np.cos(a), center_z + radius * np.sin(a)) for a in angles]
    return cap if upper else [(r, 2 * center_z - z) for r, z in reversed(cap)]


def round_profile(type_name, height, radius_bottom, radius_top):
    """Bottom-to-top (radius, z) profile of a cylinder, cone or capsule centred at the origin."""
    h = height / 2
    if type_name.startswith("Cylinder"):
        return [(0, -h), (radius_bottom, -h), (radius_top, h), (0, h)]
    if type_name == "Cone":
        return [(0, -h), (radius_bottom, -h), (0, h)]  # apex at +h along the axis
    return (hemisphere_profile(radius_bottom, -h, upper=False)
            + hemisphere_profile(radius_top, h, upper=True))  # capsule: height excludes the caps


def implicit_triangles(prim, time, warn, segments=48) -> Optional[Triangles]:
    """Tessellates UsdGeom Cube / Plane / Cylinder(_1) / Cone / Capsule(_1)."""
    type_name = prim.GetTypeName()
    schema = getattr(UsdGeom, type_name, None)
    if type_name not in IMPLICIT_TYPES or schema is None:
        warn(f"{type_name} is not supported; ignored")
        return None
    shape = schema(prim)

    def get(attribute):
        return getattr(shape, f"Get{attribute}Attr")().Get(time)
    if type_name == "Cube":
        positions, triangles = cube_triangles(float(get("Size")))
    elif type_name == "Plane":
        positions, triangles = plane_triangles(float(get("Width")), float(get("Length")), get("Axis"))
    else:
        if type_name.endswith("_1"):
            bottom, top = float(get("RadiusBottom")), float(get("RadiusTop"))
        else:
            bottom = top = float(get("Radius"))
        positions, triangles = revolve(round_profile(type_name, float(get("Height")), bottom, top), segments)
        positions = positions @ axis_frame(get("Axis"))
    return Triangles(positions, triangles).contiguous()
