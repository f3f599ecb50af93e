"""UsdGeom prims to the arrays gi._core.Scene.add_mesh takes: polygon meshes (validated,
fan-triangulated, primvars de-indexed to what the renderer wants) and tessellations of the
implicit prims the renderer has no exact shape for (cube, cylinder, cone, capsule, plane).

`warn(message)` reports a problem; the caller adds the file and prim path."""
from dataclasses import dataclass
from typing import Optional

import numpy as np
from pxr import UsdGeom

UV_PRIMVAR_NAMES = ("st", "st0", "UVMap")
IMPLICIT_TYPES = ("Cube", "Cylinder", "Cylinder_1", "Cone", "Capsule", "Capsule_1", "Plane")


@dataclass
class Triangles:
    positions: np.ndarray             # (N, 3) float32
    indices: np.ndarray               # (M, 3) uint32
    normals: Optional[np.ndarray] = None   # (N, 3) float32
    uvs: Optional[np.ndarray] = None       # (N, 2) float32
    faces: Optional[np.ndarray] = None     # (M,) int64: the authored face each triangle came from
    # (N,) int64: the authored point each vertex is (a deforming mesh's points at other times map through it)
    point_of_vertex: Optional[np.ndarray] = None

    def contiguous(self):
        """nanobind takes C-contiguous arrays of exactly these dtypes."""
        def fix(a, dtype):
            return None if a is None else np.ascontiguousarray(a, dtype=dtype)
        return Triangles(fix(self.positions, np.float32), fix(self.indices, np.uint32),
                         fix(self.normals, np.float32), fix(self.uvs, np.float32), fix(self.faces, np.int64),
                         fix(self.point_of_vertex, np.int64))

    def select(self, which):
        """The triangles `which` selects (a boolean mask or triangle numbers), over only the vertices
        they use (normals and uvs are per vertex, so they follow the vertices)."""
        indices = np.asarray(self.indices)[which]
        used, compact = np.unique(indices, return_inverse=True)

        def take(a):
            return None if a is None else a[used]
        return Triangles(self.positions[used], compact.reshape(-1, 3), take(self.normals), take(self.uvs),
                         None if self.faces is None else self.faces[which], take(self.point_of_vertex)).contiguous()


# -- polygon meshes: topology ---------------------------------------------------------------------

def usable_faces(counts, indices, points, warn):
    """Boolean mask of the faces that can be triangulated; warns once per kind of problem."""
    face_count = len(counts)
    ends = np.cumsum(counts)
    keep = counts >= 3
    if not keep.all():
        warn(f"{int((~keep).sum())} faces with fewer than 3 vertices dropped")
    past_end = ends > len(indices)
    if past_end.any():
        warn(f"faceVertexCounts sum to {int(ends[-1])} but there are {len(indices)} faceVertexIndices; "
             f"{int(past_end.sum())} faces past the end dropped")
        keep &= ~past_end
    elif face_count and ends[-1] < len(indices):
        warn(f"faceVertexCounts sum to {int(ends[-1])} but there are {len(indices)} faceVertexIndices; "
             f"the extra indices are ignored")

    covered = int(min(ends[-1], len(indices))) if face_count else 0
    # The corners of each face that exist (a count of 2^31 must not become a 2^31-element array).
    present = np.clip(np.minimum(ends, covered) - (ends - counts), 0, None)
    face_of_corner = np.repeat(np.arange(face_count), present)
    corner_points = indices[:covered]

    def faces_where(corner_is_bad):
        return np.bincount(face_of_corner[corner_is_bad], minlength=face_count) > 0

    out_of_range = (corner_points < 0) | (corner_points >= len(points))
    bad = faces_where(out_of_range) & keep
    if bad.any():
        warn(f"{int(bad.sum())} faces with out-of-range point indices (valid: 0..{len(points) - 1}) dropped")
        keep &= ~bad

    finite_point = np.isfinite(points).all(axis=1)
    uses_nonfinite = np.zeros(covered, bool)
    uses_nonfinite[~out_of_range] = ~finite_point[corner_points[~out_of_range]]
    bad = faces_where(uses_nonfinite) & keep
    if bad.any():
        warn(f"{int(bad.sum())} faces using NaN/Inf points dropped")
        keep &= ~bad
    return keep


def fan_triangulate(counts, keep):
    """Triangles (v0, vk, vk+1) of each kept polygon, as (M, 3) positions in faceVertexIndices
    ("slots"), and the face each triangle came from."""
    starts = np.cumsum(counts) - counts
    kept_counts, kept_starts = counts[keep], starts[keep]
    per_face = kept_counts - 2
    face_of_triangle = np.repeat(np.flatnonzero(keep), per_face)
    first = np.repeat(kept_starts, per_face)
    k = np.arange(per_face.sum()) - np.repeat(np.cumsum(per_face) - per_face, per_face)
    slots = np.stack([first, first + k + 1, first + k + 2], axis=1)
    return slots, face_of_triangle


# -- polygon meshes: primvars ---------------------------------------------------------------------

@dataclass
class PrimvarData:
    """Values that are either per point (shared by the corners using that point) or per corner."""
    values: np.ndarray
    per_corner: bool


def primvar_data(values, interpolation, topology, what, warn) -> Optional[PrimvarData]:
    """Resolves a flattened primvar of any interpolation against the triangulation."""
    if values is None:  # ComputeFlattened fails on out-of-range primvar indices
        warn(f"{what} has invalid indices; ignored")
        return None
    values = np.asarray(values, dtype=np.float32)
    if values.ndim != 2 or len(values) == 0:
        return None
    if not np.isfinite(values).all():
        warn(f"{what} has NaN/Inf values; ignored")
        return None
    needed = {UsdGeom.Tokens.vertex: topology.point_count, UsdGeom.Tokens.varying: topology.point_count,
              UsdGeom.Tokens.faceVarying: topology.corner_count, UsdGeom.Tokens.uniform: topology.face_count,
              UsdGeom.Tokens.constant: 1}.get(interpolation)
    if needed is None:
        warn(f"{what} has unsupported interpolation '{interpolation}'; ignored")
        return None
    if len(values) < needed:
        warn(f"{what} has {len(values)} values but its '{interpolation}' interpolation needs {needed}; ignored")
        return None
    if interpolation in (UsdGeom.Tokens.vertex, UsdGeom.Tokens.varying):
        return PrimvarData(values[:topology.point_count], per_corner=False)
    if interpolation == UsdGeom.Tokens.constant:
        return PrimvarData(np.repeat(values[:1], topology.point_count, axis=0), per_corner=False)
    if interpolation == UsdGeom.Tokens.faceVarying:
        return PrimvarData(values[topology.slots.reshape(-1)], per_corner=True)
    return PrimvarData(values[np.repeat(topology.face_of_triangle, 3)], per_corner=True)  # uniform


@dataclass
class Topology:
    point_count: int
    corner_count: int     # len(faceVertexIndices)
    face_count: int
    slots: np.ndarray     # (M, 3) positions in faceVertexIndices
    face_of_triangle: np.ndarray


def mesh_normals(mesh, time, topology, warn) -> Optional[PrimvarData]:
    """primvars:normals if authored (it wins over the normals attribute), else normals."""
    primvar = UsdGeom.PrimvarsAPI(mesh).GetPrimvar("normals")
    if primvar and primvar.HasAuthoredValue():
        return primvar_data(primvar.ComputeFlattened(time), primvar.GetInterpolation(), topology,
                            "primvars:normals", warn)
    attribute = mesh.GetNormalsAttr()
    if attribute.HasAuthoredValue():
        return primvar_data(attribute.Get(time), mesh.GetNormalsInterpolation(), topology, "normals", warn)
    return None


def uv_primvar(mesh, preferred_names=()):
    """The texture-coordinate primvar: the material's reader's name, st, st0, UVMap, else the first
    texCoord2f[] primvar."""
    api = UsdGeom.PrimvarsAPI(mesh)
    for name in (*preferred_names, *UV_PRIMVAR_NAMES):
        primvar = api.GetPrimvar(name)
        if primvar and primvar.HasAuthoredValue():
            return primvar
    for primvar in api.GetPrimvarsWithAuthoredValues():
        if str(primvar.GetTypeName()) == "texCoord2f[]":
            return primvar
    return None


def mesh_uvs(mesh, time, topology, warn, preferred_names=()) -> Optional[PrimvarData]:
    primvar = uv_primvar(mesh, preferred_names)
    if primvar is None:
        return None
    data = primvar_data(primvar.ComputeFlattened(time), primvar.GetInterpolation(), topology,
                        f"primvars:{primvar.GetPrimvarName()}", warn)
    if data is not None and data.values.shape[1] != 2:
        warn(f"primvars:{primvar.GetPrimvarName()} is not 2-dimensional; ignored")
        return None
    return data


# -- polygon meshes: assembly ---------------------------------------------------------------------

def share_points(points, vertex_index, primvars):
    """Triangles over the points the kept faces use (unused, possibly NaN, points left out)."""
    used = np.unique(vertex_index)
    remap = np.full(len(points), -1, np.int64)
    remap[used] = np.arange(len(used))
    return Triangles(points[used], remap[vertex_index],
                     *[None if p is None else p.values[used] for p in primvars], point_of_vertex=used)


def split_corners(points, vertex_index, primvars):
    """One vertex per triangle corner: needed as soon as any primvar varies per face corner."""
    corner_points = vertex_index.reshape(-1)

    def per_corner(p):
        if p is None:
            return None
        return p.values if p.per_corner else p.values[corner_points]
    indices = np.arange(len(corner_points)).reshape(-1, 3)
    return Triangles(points[corner_points], indices, *[per_corner(p) for p in primvars],
                     point_of_vertex=corner_points)


def mesh_triangles(mesh: UsdGeom.Mesh, time, warn, uv_names=()) -> Optional[Triangles]:
    """The mesh's valid faces as triangles, or None (with a warning) if none remain; `faces` holds
    the authored face index of each triangle (what GeomSubset indices refer to)."""
    points = np.asarray(mesh.GetPointsAttr().Get(time) or [], dtype=np.float64).reshape(-1, 3)
    counts = np.asarray(mesh.GetFaceVertexCountsAttr().Get(time) or [], dtype=np.int64)
    indices = np.asarray(mesh.GetFaceVertexIndicesAttr().Get(time) or [], dtype=np.int64)
    if len(points) == 0 or len(counts) == 0:
        warn("mesh has no points or no faces; ignored")
        return None
    if (counts < 0).any():
        warn("faceVertexCounts has negative counts; mesh ignored")
        return None
    keep = usable_faces(counts, indices, points, warn)
    if not keep.any():
        warn("no valid faces remain; mesh ignored")
        return None
    slots, face_of_triangle = fan_triangulate(counts, keep)
    if mesh.GetOrientationAttr().Get(time) == UsdGeom.Tokens.leftHanded:
        slots = slots[:, [0, 2, 1]]  # the renderer takes counter-clockwise (right-handed) triangles
    topology = Topology(len(points), len(indices), len(counts), slots, face_of_triangle)
    primvars = (mesh_normals(mesh, time, topology, warn), mesh_uvs(mesh, time, topology, warn, uv_names))
    vertex_index = indices[slots]
    if any(p is not None and p.per_corner for p in primvars):
        triangles = split_corners(points, vertex_index, primvars)
    else:
        triangles = share_points(points, vertex_index, primvars)
    triangles.faces = face_of_triangle
    return triangles.contiguous()


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
