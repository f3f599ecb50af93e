"""UsdGeom prims to triangle arrays: meshes (triangulated, primvars de-indexed) and the implicit
prims the renderer has no exact shape for (cube, cylinder, cone, capsule, plane)."""
from dataclasses import dataclass
from typing import Optional

import numpy as np
from pxr import UsdGeom


@dataclass
class Triangles:
    positions: np.ndarray           # (N, 3) float32
    indices: np.ndarray             # (M, 3) uint32
    normals: Optional[np.ndarray]   # (N, 3) float32 or None
    uvs: Optional[np.ndarray]       # (N, 2) float32 or None


def _fan_triangulate(counts, indices, warn, name):
    """Fan-triangulates polygons. Returns (triangle corner -> face-vertex slot) as (M, 3) and
    (triangle -> face index). Polygons with fewer than 3 vertices are dropped with a warning."""
    counts = np.asarray(counts, dtype=np.int64)
    if counts.size and (counts < 0).any():
        warn(f"mesh {name}: negative faceVertexCounts; mesh ignored")
        return np.zeros((0, 3), np.int64), np.zeros(0, np.int64)
    if counts.sum() != len(indices):
        warn(f"mesh {name}: faceVertexCounts sum to {counts.sum()} but there are {len(indices)} "
             f"faceVertexIndices; faces past the end dropped")
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]]) if counts.size else np.zeros(0, np.int64)
    small = int((counts < 3).sum())
    if small:
        warn(f"mesh {name}: {small} faces with fewer than 3 vertices dropped")
    tri_count = np.maximum(counts - 2, 0)
    face_of_tri = np.repeat(np.arange(len(counts)), tri_count)
    first = np.repeat(starts, tri_count)
    k = np.arange(tri_count.sum()) - np.repeat(np.cumsum(tri_count) - tri_count, tri_count)
    slots = np.stack([first, first + k + 1, first + k + 2], axis=1)
    in_range = (slots < len(indices)).all(axis=1)
    return slots[in_range], face_of_tri[in_range]


def _primvar(prim_api, names):
    for name in names:
        pv = prim_api.GetPrimvar(name)
        if pv and pv.HasValue():
            return pv
    return None


def _expand(values, interpolation, slots, vertex_index, face_of_tri, warn, what, name):
    """Per-corner (M*3, C) values for a primvar of any interpolation, or None if unusable."""
    values = np.asarray(values, dtype=np.float32)
    corner_count = slots.size
    if interpolation in (UsdGeom.Tokens.vertex, UsdGeom.Tokens.varying):
        lookup = vertex_index.reshape(-1)
    elif interpolation == UsdGeom.Tokens.faceVarying:
        lookup = slots.reshape(-1)
    elif interpolation == UsdGeom.Tokens.uniform:
        lookup = np.repeat(face_of_tri, 3)
    elif interpolation == UsdGeom.Tokens.constant:
        lookup = np.zeros(corner_count, np.int64)
    else:
        warn(f"mesh {name}: {what} has unsupported interpolation '{interpolation}'; ignored")
        return None
    if lookup.size and lookup.max() >= len(values):
        warn(f"mesh {name}: {what} has {len(values)} values, too few for its '{interpolation}' "
             f"interpolation; ignored")
        return None
    return values[lookup]


def mesh_triangles(mesh: UsdGeom.Mesh, time, warn) -> Optional[Triangles]:
    name = str(mesh.GetPath())
    points = np.asarray(mesh.GetPointsAttr().Get(time) or [], dtype=np.float32).reshape(-1, 3)
    counts = mesh.GetFaceVertexCountsAttr().Get(time) or []
    indices = np.asarray(mesh.GetFaceVertexIndicesAttr().Get(time) or [], dtype=np.int64)
    if len(points) == 0 or len(indices) == 0:
        warn(f"mesh {name}: no points or no faces; ignored")
        return None
    slots, face_of_tri = _fan_triangulate(counts, indices, warn, name)
    vertex_index = indices[slots]
    bad = (vertex_index < 0) | (vertex_index >= len(points))
    if bad.any():
        keep = ~bad.any(axis=1)
        warn(f"mesh {name}: {int((~keep).sum())} triangles with out-of-range point indices dropped")
        slots, face_of_tri, vertex_index = slots[keep], face_of_tri[keep], vertex_index[keep]
    if mesh.GetOrientationAttr().Get(time) == UsdGeom.Tokens.leftHanded:
        slots, vertex_index = slots[:, ::-1], vertex_index[:, ::-1]
    if len(slots) == 0:
        warn(f"mesh {name}: no valid triangles; ignored")
        return None
    if mesh.GetSubdivisionSchemeAttr().Get(time) not in (None, UsdGeom.Tokens.none):
        pass  # rendered as its control cage: subdivision is refined by the Hydra delegate (OpenSubdiv)

    api = UsdGeom.PrimvarsAPI(mesh)
    normals = None
    normal_pv = _primvar(api, ["normals"])
    if normal_pv is not None:
        normals = _expand(normal_pv.ComputeFlattened(time), normal_pv.GetInterpolation(), slots,
                          vertex_index, face_of_tri, warn, "primvars:normals", name)
    elif mesh.GetNormalsAttr().HasAuthoredValue():
        normals = _expand(mesh.GetNormalsAttr().Get(time), mesh.GetNormalsInterpolation(), slots,
                          vertex_index, face_of_tri, warn, "normals", name)
    uvs = None
    st_pv = _primvar(api, ["st", "st0", "UVMap", "uv"])
    if st_pv is not None:
        uvs = _expand(st_pv.ComputeFlattened(time), st_pv.GetInterpolation(), slots, vertex_index,
                      face_of_tri, warn, f"primvars:{st_pv.GetPrimvarName()}", name)

    # Corners become vertices when any primvar varies per corner; otherwise points are shared.
    per_corner = (normals is not None and normal_pv is not None and
                  normal_pv.GetInterpolation() != UsdGeom.Tokens.vertex) or \
                 (uvs is not None and st_pv.GetInterpolation() != UsdGeom.Tokens.vertex) or \
                 (normals is not None and normal_pv is None and
                  mesh.GetNormalsInterpolation() != UsdGeom.Tokens.vertex)
    if per_corner:
        positions = points[vertex_index.reshape(-1)]
        tri = np.arange(len(positions), dtype=np.uint32).reshape(-1, 3)
        return Triangles(positions, tri, normals, uvs)
    # Vertex interpolation: values were expanded per corner; take them back per point.
    def per_point(values):
        if values is None:
            return None
        out = np.zeros((len(points), values.shape[1]), np.float32)
        out[vertex_index.reshape(-1)] = values
        return out
    return Triangles(points, vertex_index.astype(np.uint32), per_point(normals), per_point(uvs))


def _axis_frame(axis):
    """Rows mapping a shape built along +Z onto the given axis."""
    if axis == "X":
        return np.array([[0, 0, -1], [0, 1, 0], [1, 0, 0]], np.float32)  # z -> x
    if axis == "Y":
        return np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], np.float32)  # z -> y
    return np.eye(3, dtype=np.float32)


def _revolve(profile, segments):
    """A surface of revolution around +Z from (radius, z) profile points, as Triangles."""
    angles = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    rings = [np.stack([r * np.cos(angles), r * np.sin(angles), np.full(segments, z)], axis=1)
             for r, z in profile]
    positions = np.concatenate(rings).astype(np.float32)
    tris = []
    for i in range(len(profile) - 1):
        for j in range(segments):
            a, b = i * segments + j, i * segments + (j + 1) % segments
            c, d = a + segments, b + segments
            tris += [(a, b, d), (a, d, c)]
    tris = np.array(tris, np.uint32)
    # Rings of radius 0 (the poles) make zero-area triangles: leave them out.
    p = positions[tris]
    area = np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    return positions, tris[area > 1e-12]


def implicit_triangles(prim, time, warn, segments=48) -> Optional[Triangles]:
    """Tessellates UsdGeom Cube / Cylinder / Cone / Capsule / Plane."""
    type_name = prim.GetTypeName()
    if type_name == "Cube":
        s = float(UsdGeom.Cube(prim).GetSizeAttr().Get(time)) / 2
        corners = np.array([[x, y, z] for x in (-s, s) for y in (-s, s) for z in (-s, s)], np.float32)
        quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
        tris = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))], np.uint32)
        return Triangles(corners, tris, None, None)
    if type_name == "Plane":
        plane = UsdGeom.Plane(prim)
        w, l = float(plane.GetWidthAttr().Get(time)) / 2, float(plane.GetLengthAttr().Get(time)) / 2
        quad = np.array([[-w, -l, 0], [w, -l, 0], [w, l, 0], [-w, l, 0]], np.float32)
        frame = _axis_frame(plane.GetAxisAttr().Get(time))
        return Triangles(quad @ frame, np.array([[0, 1, 2], [0, 2, 3]], np.uint32), None, None)
    if type_name in ("Cylinder", "Cone", "Capsule"):
        schema = getattr(UsdGeom, type_name)(prim)
        h = float(schema.GetHeightAttr().Get(time)) / 2
        r = float(schema.GetRadiusAttr().Get(time))
        if type_name == "Cylinder":
            profile = [(0, -h), (r, -h), (r, h), (0, h)]
        elif type_name == "Cone":
            profile = [(0, -h), (r, -h), (0, h)]
        else:
            cap = [(r * np.cos(a), h + r * np.sin(a)) for a in np.linspace(0, np.pi / 2, 9)]
            profile = [(x, -z) for x, z in reversed(cap)] + cap
        positions, tris = _revolve(profile, segments)
        return Triangles(positions @ _axis_frame(schema.GetAxisAttr().Get(time)), tris, None, None)
    warn(f"prim {prim.GetPath()}: {type_name} is not supported; ignored")
    return None
