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
import sys

import numpy as np
import pytest

from conftest import ROOT, run_gi

PARITY = ROOT / "tests" / "parity"
sys.path.insert(0, str(PARITY))
import stage_files  # noqa: E402  (tests/parity/stage_files.py: the stages with their textures)
SPP = 16
PIXEL = 0.01         # units per pixel
HALF_VIEW = 1.2      # the view spans -1.2..1.2 in x and y
EDGE_SIGMA = 0.5 / math.sqrt(SPP)   # pixels, per pixel an edge crosses
LIMIT_FACE_CENTRE = 68 / 81  # Catmull-Clark limit of a cube face's centre (test_mesh_description.cpp)
# Distance of the face-centre vertex to it after level 1 (68/81 + 0.1605 = 1: the level-1 face point),
# shrinking by 1/4 per level (the regular vertex's eigenvalue; measured 0.243, 0.248, 0.250 there).
FACE_CENTRE_EXCESS = 1 - LIMIT_FACE_CENTRE


def render(tmp_path, stage, *flags, seed=0):
    """The stage rendered by `gi render`: channel name -> (height, width) array."""
    from gi import _core
    output = tmp_path / f"{stage}{''.join(map(str, flags))}-{seed}.exr"
    scene = stage_files.prepare(stage, tmp_path / "stages")
    run_gi("render", scene, "--spp", SPP, "--seed", seed, "-o", output, "--no-png", *flags)
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


# -- shading rules (renderer/usd_shading.h) -------------------------------------------------------
# The textured stages emit their texture on the quad (-1..1)^2, so st = (x + 1) / 2, (y + 1) / 2. With
# two texels a side and wrap clamp, st in [0, 0.25] or [0.75, 1] reads one texel alone: the quad's
# corner squares (x, y within 0.5 of a corner) show their texel exactly, samples and seed aside.

def rgb(image):
    return np.stack([image["R"], image["G"], image["B"]], axis=-1)


def corner_squares():
    """(x0, x1, y0, y1) of each corner square of the quad -> the texel it shows."""
    return {(-1.0 if u < 0.5 else 0.5, -0.5 if u < 0.5 else 1.0, -1.0 if v < 0.5 else 0.5, -0.5 if v < 0.5 else 1.0):
            colour for (u, v), colour in stage_files.QUADRANTS.items()}


def assert_texture_upright(color):
    for (x0, x1, y0, y1), texel in corner_squares().items():
        square = region(color, x0, x1, y0, y1)
        assert square.size and np.array_equal(square, np.broadcast_to(texel, square.shape)), ((x0, y0), texel)
    # The bilinear, clamped 2 x 2 texture averages to its texels' mean over st [0, 1]^2 (symmetry):
    # (0.5, 0.5, 0.5). Inside a pixel the box filter's SPP jittered samples of a ramp of slope 1 per
    # unit (0.01 a pixel) deviate by 0.01 / sqrt(12 SPP) each, independently, so the quad's mean over
    # its 40 000 pixels is within 4 * 0.01 / sqrt(12 SPP) / 200 (about 3e-5) of it.
    quad = region(color, -1, 1, -1, 1, inset=0)
    assert np.abs(quad.mean(axis=(0, 1)) - 0.5).max() < 4 * 0.01 / math.sqrt(12 * SPP) / 200


def test_texture_read_through_st0(tmp_path):
    """The reader's varname (st0, through the material's interface input) names the only uv set."""
    assert_texture_upright(rgb(render(tmp_path, "texture_st0")))


def test_reader_varname_beats_a_decoy_st(tmp_path):
    """primvars:uvSet1, which the reader names, is read; the mirrored primvars:st is not."""
    assert_texture_upright(rgb(render(tmp_path, "texture_varname")))


def test_missing_texture_reads_its_fallback(tmp_path):
    """The input's own authored (1, 1, 1) is overridden by its connection: without a fallback input
    the texture reads the spec's (0, 0, 0, 1), black; with one, its value; a warning names each."""
    from gi import descriptors
    from gi.loader import load_stage
    color = rgb(render(tmp_path, "texture_missing"))
    assert (region(color, -1.0, -0.1, -0.5, 0.5) == 0).all()
    right = region(color, 0.1, 1.0, -0.5, 0.5)
    assert right.size and np.abs(right - np.float32([0.2, 0.5, 0.8])).max() < 1e-6
    loaded = load_stage(tmp_path / "stages" / "texture_missing.usda", scene=descriptors.new_scene())
    for material in ("/World/NoFallback", "/World/WithFallback"):
        assert any(material in w and "no_such_texture.exr" in w for w in loaded.warnings), loaded.warnings


def test_udim_tiles_cover_their_quarters(tmp_path):
    """tiles.<UDIM>.exr: each quarter of the quad shows its tile's colour exactly; the quarter whose
    tile (1012) is not there reads the texture's fallback. The pattern is resolved against the
    stage's folder, as UsdImaging resolves it for Hydra."""
    color = rgb(render(tmp_path, "texture_udim"))
    tiles = stage_files.UDIM_TILES["tiles.<UDIM>.exr"]
    quarters = {(-1.0, 0.0, -1.0, 0.0): tiles[1001], (0.0, 1.0, -1.0, 0.0): tiles[1002],
                (-1.0, 0.0, 0.0, 1.0): tiles[1011], (0.0, 1.0, 0.0, 1.0): stage_files.UDIM_FALLBACK}
    for (x0, x1, y0, y1), colour in quarters.items():
        quarter = region(color, x0, x1, y0, y1)
        assert quarter.size and np.abs(quarter - np.float32(colour)).max() < 1e-6, ((x0, y0), colour)


# UsdPreviewSurface's Fresnel reflectance at normal incidence for its default ior 1.5: the fallback
# material's specular lobe, which the albedo AOV adds to the diffuse colour.
F0 = ((1.5 - 1) / (1.5 + 1)) ** 2
# A quad of diffuse colour (0.25, 0.5, 0.75) (UsdPreviewSurface defaults otherwise) under the white
# dome: its mean radiance, measured over seeds 0-7 at 16 spp (standard deviation of those means at
# most 1.5e-4 over both stages' quads; a pure Lambert surface would read exactly its colour).
DISPLAY_COLOR_RADIANCE = (0.27668, 0.51669, 0.75669)
RADIANCE_TOLERANCE = 4 * 1.5e-4


def assert_display_color_shaded(image, x0, x1, colour):
    albedo = np.stack([image["albedo.R"], image["albedo.G"], image["albedo.B"]], axis=-1)
    quad = region(albedo, x0, x1, -0.5, 0.5)
    assert quad.size and np.abs(quad - (np.array(colour) + F0)).max() < 1e-6, (x0, colour)
    mean = region(rgb(image), x0, x1, -0.5, 0.5).mean(axis=(0, 1))
    expected = DISPLAY_COLOR_RADIANCE if colour[0] < colour[2] else DISPLAY_COLOR_RADIANCE[::-1]
    assert np.abs(mean - expected).max() < RADIANCE_TOLERANCE, (x0, mean)


def test_display_color_without_material(tmp_path):
    image = render(tmp_path, "display_color")
    assert_display_color_shaded(image, -1.0, 1.0, (0.25, 0.5, 0.75))
    assert (region(rgb(image), -1.2, 1.2, 0.5, 1.2) == 1).all()  # the dome, seen directly


def test_preview_surface_defaults(tmp_path):
    """A UsdPreviewSurface authoring no input and a gprim with neither material nor displayColor
    are both the spec's defaults: albedo 0.18 plus the 1.5 IOR's F0, exactly, and (sample noise
    apart) the same radiance: the halves' means (98 x 98 pixels each) agree to 4 sigma of their
    difference, the per-pixel standard deviation measured 0.0072 at 16 spp (seeds 0-3; the halves'
    means then differed by 1.2e-5 to 1.2e-4)."""
    image = render(tmp_path, "preview_surface_defaults")
    albedo = np.stack([image["albedo.R"], image["albedo.G"], image["albedo.B"]], axis=-1)
    for x0, x1 in ((-1.0, 0.0), (0.0, 1.0)):
        assert np.abs(region(albedo, x0, x1, -0.5, 0.5) - (0.18 + F0)).max() < 1e-6, x0
    bound, unbound = (region(rgb(image), x0, x1, -0.5, 0.5).mean() for x0, x1 in ((-1.0, 0.0), (0.0, 1.0)))
    assert abs(bound - unbound) < 4 * math.sqrt(2) * 0.0072 / 98, (bound, unbound)


def test_display_color_is_inherited(tmp_path):
    image = render(tmp_path, "display_color_inherited")
    assert_display_color_shaded(image, -1.0, -0.1, (0.25, 0.5, 0.75))   # the parent's
    assert_display_color_shaded(image, 0.1, 1.0, (0.75, 0.5, 0.25))     # its own


def test_geom_subsets_bind_their_materials(tmp_path):
    """Left to right: subset RedFaces' material, the mesh's own (Green), subset BlueFaces'. All edges
    are on pixel edges: each quad's pixels are its colour exactly, the gaps black."""
    color = rgb(render(tmp_path, "geom_subsets"))
    for (x0, x1), colour in (((-1.0, -0.4), (1, 0, 0)), ((-0.3, 0.3), (0, 1, 0)), ((0.4, 1.0), (0, 0, 1))):
        quad = region(color, x0, x1, -0.5, 0.5, inset=0)
        assert np.array_equal(quad, np.broadcast_to(np.float64(colour), quad.shape)), colour
    assert area(color.sum(axis=-1)) == pytest.approx(3 * 0.6, abs=1e-4)


def test_emissive_subsets_light_the_floor_each_with_its_material(tmp_path):
    """The warm subset (A, bound to Looks/Y) hangs beside the view's left edge, the cool one (B,
    Looks/X) beside its right: the floor's left edge is lit warm (red over blue about 2, less the
    far lamp's share), its right edge cool; both are sampled as lights (4 emissive triangles).
    tests/hydra/test_parity.py checks that usdrecord picks the same lamp for the same sample."""
    color = rgb(render(tmp_path, "emissive_subsets"))
    left, right = region(color, -1.2, -1.0, -0.1, 0.1).mean(axis=(0, 1)), region(color, 1.0, 1.2, -0.1, 0.1).mean(axis=(0, 1))
    assert left[0] > 1.5 * left[2] and right[2] > 1.5 * right[0], (left, right)
    assert np.isfinite(color).all()


@pytest.mark.parametrize("stage", ["emissive_instances", "emissive_point_instances"])
def test_emissive_instances_are_each_sampled_as_lights(tmp_path, stage):
    """Twelve lamp instances (native, or by a point instancer), each two emissive triangles, are
    24 lights, named so that they sort in the same order in both hosts (instances by path, points by
    zero-padded index: tests/hydra/test_parity.py compares the two hosts' photon images)."""
    from gi import _core
    from gi.loader import load_stage
    loaded = load_stage(str(stage_files.prepare(stage, tmp_path)))
    assert loaded.counts["instances"] == 12
    loaded.scene.commit()
    assert loaded.scene.stats()["emissive_triangles"] == 24
    color = rgb(render(tmp_path, stage))
    assert np.isfinite(color).all() and color.mean() > 0


def test_instances_keep_their_prototypes_materials(tmp_path):
    """Each tile shows its prototype's own material; nothing of the abstract /Prototypes is drawn."""
    color = rgb(render(tmp_path, "instanced_materials"))
    warm, cool = np.float32([1, 0.5, 0.25]), np.float32([0.25, 0.5, 1])
    for (x, y), colour in (((-0.6, 0.6), warm), ((0.6, -0.6), warm), ((0.6, 0.6), cool), ((-0.6, -0.6), cool)):
        tile = region(color, max(x - 0.5, -1.2), min(x + 0.5, 1.2), max(y - 0.5, -1.2), min(y + 0.5, 1.2), inset=0)
        assert np.abs(tile - colour).max() < 1e-6, (x, y)
    assert area(color[..., 1]) == pytest.approx(4 * 1.0 * 0.5, abs=1e-4)  # green 0.5 on 4 unit tiles


def window_of(width, height):
    """camera_offsets.usda's window (left, top, pixel size) at width x height, expanded about its
    centre (0.3, -0.2) to the image's aspect (renderer/camera.h's expandAperture)."""
    aperture_w, aperture_h = 2.4, 1.625
    if aperture_w / aperture_h < width / height:
        aperture_w = aperture_h * width / height
    else:
        aperture_h = aperture_w * height / width
    return 0.3 - aperture_w / 2, -0.2 + aperture_h / 2, aperture_w / width


@pytest.mark.parametrize("resolution", [(240, 162), (240, 240)])
def test_camera_aperture_offsets_and_conform(tmp_path, resolution):
    """The rectangle x -0.5..1, y -0.75..0.25 lands where the offsets and the expanded window put it.
    At 240 x 162 (usdrecord's size for this camera) the window's width grows 0.3% to the image's
    aspect: the rectangle is 149.54 pixels wide, not the 150.0 of a stretched window. At 240 x 240
    the height grows to 2.4 units. Noise: a row's width has two edge pixels, each of standard
    deviation 0.5 / sqrt(SPP) pixels; its mean over R rows, 4 sigma, is 4 sqrt(2) 0.5 / sqrt(SPP R)."""
    width, height = resolution
    covered = render(tmp_path, "camera_offsets", "--resolution", width, height)["R"]
    assert covered.shape == (height, width)
    left, top, pixel = window_of(width, height)
    rows = covered.sum(axis=1)
    full = rows > 0.99 * rows.max()  # rows wholly inside the rectangle's height
    row_width = rows[full].mean()
    noise = 4 * math.sqrt(2) * 0.5 / math.sqrt(SPP * full.sum())
    print(f"{width}x{height}: rectangle {row_width:.3f} pixels wide (expected {1.5 / pixel:.3f} +- {noise:.3f})")
    assert row_width == pytest.approx(1.5 / pixel, abs=noise)
    # Its centre (0.25, -0.25) in pixels, from the covered pixels' centroid. Noise: the edge pixels
    # across x (two edges of h pixels, at +-w/2 from the centre, each EDGE_SIGMA) move the x centroid
    # by EDGE_SIGMA (w / 2) sqrt(2 h) / area, and likewise in y; 4 sigma of the larger.
    ys, xs = np.indices(covered.shape) + 0.5
    total = covered.sum()
    centre = ((covered * xs).sum() / total, (covered * ys).sum() / total)
    expected = ((0.25 - left) / pixel, (top + 0.25) / pixel)
    w, h = 1.5 / pixel, 1.0 / pixel
    centre_noise = 4 * EDGE_SIGMA * max(w / 2 * math.sqrt(2 * h), h / 2 * math.sqrt(2 * w)) / (w * h)
    print(f"centre {centre[0]:.3f}, {centre[1]:.3f} pixels (expected {expected[0]:.3f}, {expected[1]:.3f} "
          f"+- {centre_noise:.3f})")
    assert np.abs(np.subtract(centre, expected)).max() < centre_noise
    perimeter = 2 * (1.5 + 1.0) / pixel
    assert total * pixel ** 2 == pytest.approx(1.5, abs=4 * EDGE_SIGMA * math.sqrt(perimeter) * pixel ** 2)


def conform_window(policy, pixel_aspect, width=240, height=120):
    """camera_conform.usda's window in the rectangle's plane (5 units away): (left, top, pixel width,
    pixel height) in scene units after `policy` conforms the 24.3 x 16.5 aperture (focal length 30,
    offsets 3.3 and -2) to the image's aspect (pixel_aspect * width / height), about its centre."""
    half_w, half_h = 5 * 0.5 * 24.3 / 30, 5 * 0.5 * 16.5 / 30
    centre_x, centre_y = 5 * 3.3 / 30, 5 * -2 / 30
    aspect = pixel_aspect * width / height
    wider = half_w / half_h > aspect
    if policy == "adjustApertureWidth" or (policy == "expandAperture" and not wider) or \
            (policy == "cropAperture" and wider):
        half_w = half_h * aspect
    elif policy in ("adjustApertureHeight", "expandAperture", "cropAperture"):
        half_h = half_w / aspect
    return centre_x - half_w, centre_y + half_h, 2 * half_w / width, 2 * half_h / height


@pytest.mark.parametrize("policy, pixel_aspect", stage_files.CONFORM_CASES)
def test_conform_policy_frames_the_rectangle(tmp_path, policy, pixel_aspect):
    """The render settings' aspectRatioConformPolicy and pixelAspectRatio set where the rectangle
    x -0.5..1.5, y -1..0.5 lands in the 240 x 120 image and how large it is (each case differs
    from the schema's default, expandAperture with square pixels, by at least 12 pixels in width
    or height). Noise as test_camera_aperture_offsets_and_conform's: 4 sigma of the mean of R rows'
    (or columns') two edge pixels, and of the centroid."""
    from gi import _core
    scene = stage_files.prepare("camera_conform", tmp_path / "stage")
    layer = stage_files.conform_layer(tmp_path / "stage/conform.usda", scene, policy, pixel_aspect)
    output = tmp_path / "conform.exr"
    run_gi("render", layer, "--spp", SPP, "--seed", 0, "-o", output, "--no-png")
    pixels, meta = _core.read_image(str(output))
    covered = np.asarray(pixels, np.float64)[..., meta["channels"].index("R")]
    assert covered.shape == (120, 240)
    left, top, pixel_w, pixel_h = conform_window(policy, pixel_aspect)
    w, h = 2.0 / pixel_w, 1.5 / pixel_h  # the rectangle in pixels
    rows, columns = covered.sum(axis=1), covered.sum(axis=0)
    full_rows, full_columns = rows > 0.99 * rows.max(), columns > 0.99 * columns.max()
    width, height = rows[full_rows].mean(), columns[full_columns].mean()
    width_noise = 4 * math.sqrt(2) * EDGE_SIGMA / math.sqrt(full_rows.sum())
    height_noise = 4 * math.sqrt(2) * EDGE_SIGMA / math.sqrt(full_columns.sum())
    print(f"{policy} {pixel_aspect}: {width:.3f} x {height:.3f} pixels (expected {w:.3f} +- {width_noise:.3f} "
          f"x {h:.3f} +- {height_noise:.3f})")
    assert width == pytest.approx(w, abs=width_noise) and height == pytest.approx(h, abs=height_noise)
    ys, xs = np.indices(covered.shape) + 0.5
    total = covered.sum()
    centre = ((covered * xs).sum() / total, (covered * ys).sum() / total)
    expected = ((0.5 - left) / pixel_w, (top + 0.25) / pixel_h)
    centre_noise = 4 * EDGE_SIGMA * max(w / 2 * math.sqrt(2 * h), h / 2 * math.sqrt(2 * w)) / (w * h)
    assert np.abs(np.subtract(centre, expected)).max() < centre_noise, (centre, expected)


def test_conform_cases_differ_from_the_default():
    """Each case of CONFORM_CASES frames the rectangle visibly otherwise than expandAperture with
    square pixels (so the test above cannot pass with the policy ignored)."""
    _, _, default_w, default_h = conform_window("expandAperture", 1.0)
    for policy, pixel_aspect in stage_files.CONFORM_CASES:
        _, _, pixel_w, pixel_h = conform_window(policy, pixel_aspect)
        assert max(abs(2 / pixel_w - 2 / default_w), abs(1.5 / pixel_h - 1.5 / default_h)) > 12, policy


def test_bad_framing_settings_warn_and_fall_back(tmp_path):
    """An aspectRatioConformPolicy the schema does not allow, or a pixelAspectRatio that is not a
    positive number, warns naming the settings prim and renders with the schema's fallback; the
    render settings object refuses an unknown token, naming it."""
    from gi.loader import load_stage
    from gi.render import render_settings
    scene = stage_files.prepare("camera_conform", tmp_path / "stage")
    layer = stage_files.conform_layer(tmp_path / "stage/bad.usda", scene, "fit", -2.0)
    loaded = load_stage(layer)
    assert loaded.framing == ("expandAperture", 1.0)
    assert any("/Render/Settings" in w and "aspectRatioConformPolicy 'fit'" in w for w in loaded.warnings)
    assert any("/Render/Settings" in w and "pixelAspectRatio -2" in w for w in loaded.warnings)
    settings = render_settings(loaded, "path", {}, 1, 0, 0, 0, None, "box")
    assert (settings.aspect_ratio_conform_policy, settings.pixel_aspect_ratio) == ("expandAperture", 1.0)
    with pytest.raises(ValueError, match="'fit'"):
        settings.aspect_ratio_conform_policy = "fit"


def test_a_stage_without_a_camera_is_framed_as_usdrecord_frames_it(tmp_path):
    """no_camera.usda names no camera: `gi render` frames it with usdrecord's free camera
    (renderer/camera_framing.h), a default 50 mm camera whose horizontal field of view the quad's
    half-diagonal sqrt(1.25) just fills at distance d = sqrt(1.25) / (20.955 / 100). At usdrecord's
    240 x 175 (expandAperture widens the 20.955 x 15.2908 aperture to the image's aspect) the quad
    spans 2 / d over a window 2 * 0.152908 * 240 / 175 wide, and 1 / d over one 2 * 0.152908 high,
    centred. A pixel an edge crosses may or may not show the quad: the count of pixels showing it
    lies between the rectangle shrunk and grown by one pixel on each side."""
    image = rgb(render(tmp_path, "no_camera", "--resolution", 240, 175))
    assert image.shape[:2] == (175, 240)
    distance = math.sqrt(1.25) / (20.955 / 100)
    half_height = 0.152908
    width_px = 2 / distance / (2 * half_height * 240 / 175) * 240
    height_px = 1 / distance / (2 * half_height) * 175
    quad = (image != 1).any(axis=-1)
    count = int(quad.sum())
    assert (width_px - 2) * (height_px - 2) <= count <= (width_px + 2) * (height_px + 2), (count, width_px, height_px)
    rows, columns = np.nonzero(quad)
    assert abs((columns.min() + columns.max() + 1) / 2 - 120) <= 1 and abs((rows.min() + rows.max() + 1) / 2 - 87.5) <= 1
