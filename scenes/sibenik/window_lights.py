"""Prints the UsdLux rect lights of scenes/sibenik/sibenik.usda: one in each window opening of the
cathedral, measured from the window glass (extras/staklo.obj) and the stained glass of the rose
window (sibenik.obj), facing inward, 5 cm inside the glass. Run once by hand; its output is pasted
into sibenik.usda (the lights do not change unless the model does). With --portals it prints
UsdLux portal lights over the same openings instead, 5 cm outside the glass, light passing inward
(for sibenik_sky_portals.usda).

    .venv/bin/python scenes/sibenik/window_lights.py [--portals] [ASSETS]   # default ../shared/assets"""
import sys
from pathlib import Path

import numpy as np

from gi import _core  # noqa: E402  (the installed package: scripts/build.sh)

DOME_CENTER_X = 7.6   # the drum of the dome is centred on x = 7.6, z = 0
INSET = 0.05          # metres inside the glass


def triangles(mesh):
    return mesh["points"][mesh["face_vertex_indices"].reshape(-1, 3)]


def components(tris, decimals=4):
    """Connected sets of triangles (sharing a vertex position)."""
    keys = [tuple(np.round(v, decimals)) for v in tris.reshape(-1, 3)]
    ids = {k: i for i, k in enumerate(dict.fromkeys(keys))}
    parent = list(range(len(ids)))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x
    vertex = np.array([ids[k] for k in keys]).reshape(-1, 3)
    for a, b, c in vertex:
        for u, v in ((a, b), (b, c)):
            ru, rv = find(u), find(v)
            if ru != rv:
                parent[ru] = rv
    groups = {}
    for t, (a, _, _) in enumerate(vertex):
        groups.setdefault(find(a), []).append(t)
    return [tris[ts] for ts in groups.values()]


def plane(tris):
    cross = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    n = cross.sum(axis=0)
    n /= np.linalg.norm(n)
    center = tris.reshape(-1, 3).mean(axis=0)
    axis = np.array([DOME_CENTER_X if center[1] > 6 else 0.0, center[1], 0.0])
    return (n if np.dot(axis - center, n) > 0 else -n), center


def windows(pieces, gap=0.35):
    """Merges coplanar pieces closer than `gap` into one window each."""
    items = []
    for tris in pieces:
        n, c = plane(tris)
        items.append([n, float(np.dot(n, c)), tris.reshape(-1, 3).min(0), tris.reshape(-1, 3).max(0), [tris]])
    merged = True
    while merged:
        merged = False
        for i in range(len(items)):
            for j in range(i + 1, len(items)):
                a, b = items[i], items[j]
                if np.dot(a[0], b[0]) > 0.99 and abs(a[1] - b[1]) < 0.05 and \
                        np.all(a[2] - gap <= b[3]) and np.all(b[2] - gap <= a[3]):
                    a[2], a[3] = np.minimum(a[2], b[2]), np.maximum(a[3], b[3])
                    a[4] += b[4]
                    del items[j]
                    merged = True
                    break
            if merged:
                break
    return [(n, np.concatenate(parts)) for n, _, _, _, parts in items]


def rect(n, tris, outside=False):
    up = np.array([0.0, 1.0, 0.0])
    z = -n                                  # a rect light emits along its -Z: inward
    x = np.cross(up, z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    p = tris.reshape(-1, 3)
    u, v, w = p @ x, p @ y, p @ n
    depth = w.min() - INSET if outside else w.max() + INSET
    center = x * (u.min() + u.max()) / 2 + y * (v.min() + v.max()) / 2 + n * depth
    return x, y, z, center, float(u.max() - u.min()), float(v.max() - v.min())


def main():
    args = [a for a in sys.argv[1:] if a != "--portals"]
    portals = "--portals" in sys.argv[1:]
    assets = Path(args[0] if args else "../shared/assets") / "sibenik"
    glass = triangles(_core.read_obj(str(assets / "extras" / "staklo.obj"))["meshes"][0])
    cathedral = _core.read_obj(str(assets / "sibenik.obj"))
    names = [m["name"] for m in cathedral["materials"]]
    stained = [triangles(m) for m in cathedral["meshes"] if names[m["material"]].startswith("staklo_")]
    found = windows(components(glass) + stained)
    found = [w for w in found if rect(*w)[4] * rect(*w)[5] > 0.02]
    found.sort(key=lambda w: tuple(np.round(rect(*w)[3], 2)))
    for i, w in enumerate(found):
        x, y, z, c, width, height = rect(*w, outside=portals)
        rows = ", ".join("(" + ", ".join(f"{v:.6g}" for v in (*axis, 0.0)) + ")" for axis in (x, y, z))
        kind = 'PortalLight "Portal' if portals else 'RectLight "Window'
        schemas = "" if portals else ' (prepend apiSchemas = ["ShadowAPI"])'
        print(f'        def {kind}_{i:02d}"{schemas}\n        {{\n'
              f'            float inputs:width = {width:.3f}\n            float inputs:height = {height:.3f}\n'
              f'            matrix4d xformOp:transform = ( {rows}, ({c[0]:.4f}, {c[1]:.4f}, {c[2]:.4f}, 1) )\n'
              f'            uniform token[] xformOpOrder = ["xformOp:transform"]\n        }}\n')
    print(f"# {len(found)} windows", file=sys.stderr)


if __name__ == "__main__":
    main()
