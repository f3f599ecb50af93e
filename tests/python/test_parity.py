"""The mesh parity stages (tests/parity/*.usda, one per rule of renderer/mesh_description.h) rendered
by `gi render` and checked against statistics the rule implies; tests/hydra/test_parity.py renders
the same stages with usdrecord and compares the two hosts' images where OpenUSD is built.

Every stage looks down -z through a 2.4 x 2.4 orthographic view at 240 x 240 (a pixel is 0.01 units;
x, y = +-1 and +-0.5 fall on pixel edges) at surfaces that only emit 1: a pixel's colour is the
fraction of it they cover (box filter, SPP samples), its depth the largest float where nothing is hit.

Noise bound used below: a pixel cut by an edge reads the fraction of its SPP samples inside, with a
standard deviation at most 0.5 / sqrt(SPP) pixels; over P such pixels at most 0.5 sqrt(P / SPP).
Tolerances are 4 of those sigmas."""
import math

import numpy as np
import pytest

from conftest import ROOT, run_gi

PARITY = ROOT / "tests" / "parity"
SPP = 16
PIXEL = 0.01         # units per pixel
HALF_VIEW = 1.2      # the view spans -1.2..1.2 in x and y
EDGE_SIGMA = 0.5 / math.sqrt(SPP)   # pixels, per pixel an edge crosses
LIMIT_FACE_CENTRE = 68 / 81  # Catmull-Clark limit of a cube face's centre (test_mesh_description.cpp)
# Distance of the face-centre vertex to it after level 1 (68/81 + 0.1605 = 1: the level-1 face point),
# shrinking by 1/4 per level (the regular vertex's eigenvalue; measured 0.243, 0.248, 0.250 there).
FACE_CENTRE_EXCESS = 1 - LIMIT_FACE_CENTRE


def render(tmp_path, stage, *flags):
    """The stage rendered by `gi render` (seed 0): channel name -> (240, 240) array."""
    from gi import _core
    output = tmp_path / f"{stage}{''.join(flags)}.exr"
    run_gi("render", PARITY / f"{stage}.usda", "--spp", SPP, "--seed", 0, "-o", output, "--no-png", *flags)
    pixels, meta = _core.read_image(str(output))
    pixels = np.asarray(pixels, np.float64)
    return {name: pixels[..., i] for i, name in enumerate(meta["channels"])}


def region(image, x0, x1, y0, y1, inset=1):
    """The pixels wholly inside x0..x1, y0..y1 (scene units), less `inset` pixels along each side."""
    c0, c1 = round((x0 + HALF_VIEW) / PIXEL) + inset, round((x1 + HALF_VIEW) / PIXEL) - inset
    r0, r1 = round((HALF_VIEW - y1) / PIXEL) + inset, round((HALF_VIEW - y0) / PIXEL) - inset
    return image[r0:r1, c0:c1]


def row(y):
    """The pixel row whose span holds height y (just below it when y is on a pixel edge)."""
    return int((HALF_VIEW - y) / PIXEL + 1e-6)


def area(image):
    return float(image.sum()) * PIXEL ** 2


def test_holes_see_the_background(tmp_path):
    image = render(tmp_path, "holes")
    covered, depth = image["R"], image["Z"]
    # The two hole faces (the centre, and the top-left one the view clips to 0.7 x 0.7): nothing.
    for hole in (region(covered, -0.5, 0.5, -0.5, 0.5), region(covered, -1.2, -0.5, 0.5, 1.2)):
        assert hole.size > 0 and (hole == 0).all()
    assert (region(depth, -0.5, 0.5, -0.5, 0.5) == np.finfo(np.float32).max).all()
    # Every other face, wholly.
    for x0, y0 in ((-1.5, -1.5), (-0.5, -1.5), (0.5, -1.5), (-1.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5)):
        assert (region(covered, max(x0, -1.2), min(x0 + 1, 1.2), max(y0, -1.2), min(y0 + 1, 1.2)) == 1).all()
    # All edges lie on pixel edges: the covered area is exact, the view less the holes' 1 + 0.49.
    assert area(covered) == pytest.approx(2.4 ** 2 - 1.49, abs=1e-4)


def projected_area_and_perimeter(refine_level):
    """The xy-projection of subdivision.usda's cube tessellated at refine_level (by the renderer's
    rules, through the loader): its convex hull's area and perimeter (the refined meshes are convex)."""
    from pxr import Usd, UsdGeom

    from gi.geometry import mesh_triangles
    stage = Usd.Stage.Open(str(PARITY / "subdivision.usda"))
    pieces = mesh_triangles(UsdGeom.Mesh(stage.GetPrimAtPath("/World/Cube")), Usd.TimeCode.Default(),
                            lambda message: None, refine_level=refine_level)
    points = np.unique(np.round(pieces[0].positions[:, :2].astype(np.float64), 9), axis=0)
    def turn(a, b, c):  # > 0: a, b, c turn counter-clockwise
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    hull = []  # Andrew's monotone chain, counter-clockwise
    for sweep in (points, points[::-1]):
        chain = []
        for p in sweep:
            while len(chain) >= 2 and turn(chain[-2], chain[-1], p) <= 0:
                chain.pop()
            chain.append(p)
        hull += chain[:-1]
    hull = np.array(hull)
    following = np.roll(hull, -1, axis=0)
    area = 0.5 * float(np.sum(hull[:, 0] * following[:, 1] - following[:, 0] * hull[:, 1]))
    return area, float(np.linalg.norm(following - hull, axis=1).sum())


@pytest.mark.parametrize("complexity, level", [(None, 0), ("medium", 1), ("high", 2), ("veryhigh", 3)])
def test_subdivision_follows_the_complexity(tmp_path, complexity, level):
    """No flag is usdrecord's default, low: the cage. Each level up, the silhouette shrinks towards the
    limit surface's: its area is the tessellation's projected area, its width through the centre
    twice the face-centre vertex's distance, between 68/81 and 68/81 + (1 - 68/81) / 4^(level - 1)."""
    covered = render(tmp_path, "subdivision", *(["--complexity", complexity] if complexity else []))["R"]
    expected, perimeter = projected_area_and_perimeter(level)
    tolerance = 4 * EDGE_SIGMA * math.sqrt(perimeter / PIXEL) * PIXEL ** 2
    print(f"level {level}: rendered area {area(covered):.5f}, tessellation's {expected:.5f} (+-{tolerance:.5f})")
    assert area(covered) == pytest.approx(expected, abs=tolerance)
    # The limit solid holds the hull of its limit points (corners at +-1/2, face centres at 68/81):
    # projected, an octagon of area 1 + 2 (68/81 - 1/2); each level's mesh holds the limit solid.
    assert 1 + 2 * (LIMIT_FACE_CENTRE - 0.5) < expected <= 4
    # The rows either side of y = 0. Half a pixel off the centre, the silhouette may come in by at
    # most half a pixel more (its slope there is under 1); two edge pixels of noise, 4 sigma.
    noise = 4 * EDGE_SIGMA * math.sqrt(2) * PIXEL
    for r in (row(0.0), row(0.0) - 1):
        width = float(covered[r].sum()) * PIXEL
        if level == 0:
            assert width == pytest.approx(2.0, abs=1e-6)
        else:
            high = 2 * (LIMIT_FACE_CENTRE + FACE_CENTRE_EXCESS / 4 ** (level - 1))
            assert 2 * LIMIT_FACE_CENTRE - PIXEL - noise < width < high + noise, (level, width)


def test_creases_and_corners_stay_sharp(tmp_path):
    """The +y face's edges infinitely sharp: that face stays flat at y = 1 out to its crease curve, a
    cubic B-spline of the face's corners reaching x = +-44/48 at z = 0 ((-1 + 23 + 23 - 1) / 48), so
    the row just under y = 1 is covered at least that wide; the smooth cube's top is at 68/81. The
    sharp corner at (1, -1, 1): the surface reaches it, so the 3 x 3 pixels inside the view's
    (1, -1) corner are partly covered; the other bottom corner, smooth, leaves its pixels empty."""
    sharp = render(tmp_path, "subdivision_creases_corners", "--complexity", "veryhigh")["R"]
    smooth = render(tmp_path, "subdivision", "--complexity", "veryhigh")["R"]
    top = row(1.0)
    width = float(sharp[top].sum()) * PIXEL
    print(f"top row: {width:.4f} creased, {smooth[top].sum() * PIXEL:.4f} smooth")
    assert 2 * 44 / 48 - 2 * PIXEL <= width <= 2.0
    assert smooth[top].sum() == 0 and sharp[top - 1].sum() == 0
    corner = region(sharp, 0.97, 1.0, -1.0, -0.97, inset=0).sum()
    print(f"pixels covered by the sharp corner's 3x3 block: {corner:.3f}")
    assert corner > 1.0
    assert region(sharp, -1.0, -0.97, -1.0, -0.97, inset=0).sum() == 0
    assert region(smooth, 0.97, 1.0, -1.0, -0.97, inset=0).sum() == 0


def test_left_handed_faces_its_winding(tmp_path):
    """Both quads are one-sided and wound clockwise seen from the camera: the leftHanded one faces it
    (and emits towards it), the rightHanded one turns its back."""
    covered = render(tmp_path, "left_handed")["R"]
    assert (region(covered, -1.0, -0.1, -0.5, 0.5) == 1).all()
    assert (region(covered, 0.1, 1.0, -0.5, 0.5) == 0).all()


def test_indexed_face_varying_normals(tmp_path):
    """The normal AOV of each face is its own corners' value (through the primvar's indices), hard
    across the shared edge."""
    image = render(tmp_path, "face_varying_normals")
    normal = np.stack([image["N.X"], image["N.Y"], image["N.Z"]], axis=-1)
    left, right = region(normal, -1.0, 0.0, -0.5, 0.5), region(normal, 0.0, 1.0, -0.5, 0.5)
    assert np.abs(left - (0, 0, 1)).max() < 1e-6
    assert np.abs(right - (0.6, 0, 0.8)).max() < 1e-6
