"""`gi reference` and `gi study` end to end on a tiny Cornell box, and the statistics behind them."""
import csv
import json
import math

import numpy as np
import pytest

from conftest import run_gi

BUDGETS = (0.3, 0.6)
SIZE = (32, 32)


def study_integrators():
    """Two integrators from the registry: the path tracer and the one without indirect light."""
    from gi import _core
    names = [info["name"] for info in _core.integrators()]
    assert "path" in names and "direct" in names, names
    return ["path", "direct"]


def read_meta(path):
    from gi import _core
    pixels, meta = _core.read_image(str(path))
    return pixels, meta


@pytest.fixture(scope="module")
def tiny_study(tmp_path_factory):
    """A 32x32 reference and a study of two integrators at two budgets, made once for this module."""
    from conftest import CORNELL
    folder = tmp_path_factory.mktemp("study")
    reference = folder / "ref.exr"
    # A target out of reach, so the time limit decides how good the reference is.
    run_gi("reference", CORNELL, "-o", reference, "--resolution", *SIZE, "--max-seconds", 2,
           "--target-error", 1e-6)
    out = folder / "out"
    proc = run_gi("study", CORNELL, "--reference", reference, "--integrators", ",".join(study_integrators()),
                  "--budgets", ",".join(map(str, BUDGETS)), "--resolution", *SIZE, "-o", out)
    with open(out / "results.csv", newline="") as stream:
        rows = list(csv.DictReader(stream))
    return {"out": out, "reference": reference, "rows": rows, "stdout": proc.stdout}


def run_rows(tiny_study):
    return [row for row in tiny_study["rows"] if row["label"] != "reference"]


def rendered_rows(tiny_study):
    """The runs as rendered (the denoised rows left out)."""
    return [row for row in run_rows(tiny_study) if not row["integrator"].endswith(" + denoise")]


def oidn_installed():
    from gi.denoise import open_denoiser
    from gi.errors import DenoiserMissing
    try:
        open_denoiser()
        return True
    except DenoiserMissing:
        return False


# -- the study's outputs -------------------------------------------------------------------------

def test_study_writes_every_output(tiny_study):
    from gi.study import RUN_COLUMNS, slug
    out, rows = tiny_study["out"], tiny_study["rows"]
    assert set(RUN_COLUMNS) <= set(rows[0])
    assert [row["label"] for row in rows][0] == "reference"
    runs = run_rows(tiny_study)
    # Every integrator at every budget, and the path tracer's runs denoised (study.DEFAULT_DENOISED).
    techniques = study_integrators() + (["path + denoise"] if oidn_installed() else [])
    assert sorted((row["integrator"], float(row["budget_seconds"])) for row in runs) == \
        sorted((name, b) for name in techniques for b in BUDGETS)
    for name in ("error_vs_time.png", "reference.png", "difference_palette.png", "report.md", "report.html"):
        assert (out / name).stat().st_size > 0, name
    from matplotlib import image as mpimg
    assert mpimg.imread(out / "error_vs_time.png").shape[:2] == (450, 1100)
    for row in runs:
        name = slug(row["label"])
        for path in (f"{name}.exr", f"{name}.png", f"{name}_difference.png"):
            assert (out / "runs" / path).stat().st_size > 0, path
        difference = mpimg.imread(out / "runs" / f"{name}_difference.png")
        assert difference.shape[:2] == SIZE
        # Every difference image uses the palette: black, green, yellow or red mixes, never blue.
        assert difference[..., 2].max() == 0


def test_report_html_is_self_contained_and_lists_every_run(tiny_study):
    text = (tiny_study["out"] / "report.html").read_text()
    runs = run_rows(tiny_study)
    # the plot and the palette, then the reference, the render and the difference for every run
    assert text.count("data:image/png;base64,") == 2 + 3 * len(runs)
    assert 'src="runs/' not in text and 'src="reference.png"' not in text
    for row in runs:
        assert row["label"] in text
    assert "Equal time: 0.3 s" in text and "RMSE sRGB8 (0-255) by budget" in text
    markdown = (tiny_study["out"] / "report.md").read_text()
    assert all(row["label"] in markdown for row in runs) and "![error against time](error_vs_time.png)" in markdown


def test_reference_against_itself_scores_zero(tiny_study):
    check = tiny_study["rows"][0]
    assert float(check["rmse_srgb8"]) == 0.0 and float(check["rmse_linear"]) == 0.0
    assert float(check["relative_mse"]) == 0.0 and float(check["flip"]) == 0.0
    assert float(check["luminance_ratio"]) == 1.0
    _, meta = read_meta(tiny_study["reference"])
    assert check["spp"] == meta["gi:spp"]


def test_study_numbers_are_sane(tiny_study):
    runs = {(row["integrator"], float(row["budget_seconds"])): row for row in run_rows(tiny_study)}
    for (name, budget), row in runs.items():
        seconds = float(row["seconds"])
        # The renderer stops after the pass that crosses the budget, so never before it.
        assert seconds >= budget, row
        denoise_seconds = float(row["denoise_seconds"] or 0)
        assert float(row["preprocess_seconds"]) + float(row["render_seconds"]) + denoise_seconds == \
            pytest.approx(seconds, abs=0.05)
        assert 0 < float(row["rmse_srgb8"]) < 255 and math.isfinite(float(row["rmse_linear"]))
        assert 0 <= float(row["flip"]) <= 1 and float(row["peak_memory_mb"]) > 10
        assert int(row["non_finite_samples"]) == 0
    for name in study_integrators():
        assert int(runs[name, BUDGETS[1]]["spp"]) > int(runs[name, BUDGETS[0]]["spp"]), name
    # The path tracer carries all the light; direct lighting misses the indirect part.
    for budget in BUDGETS:
        path, direct = runs["path", budget], runs["direct", budget]
        assert float(path["luminance_ratio"]) == pytest.approx(1.0, abs=0.05)
        assert float(direct["luminance_ratio"]) < 0.95
        assert float(path["rmse_srgb8"]) < float(direct["rmse_srgb8"])


def test_study_rejects_a_resolution_other_than_the_references(tiny_study, cornell, tmp_path):
    proc = run_gi("study", cornell, "--reference", tiny_study["reference"], "--integrators", "path",
                  "--budgets", "0.1", "--resolution", 16, 16, "-o", tmp_path, check=False)
    assert proc.returncode == 2 and "does not match the reference's 32x32" in proc.stderr


# -- parameter tables ----------------------------------------------------------------------------

def test_params_table_runs_at_fixed_parameters(tiny_study, cornell, tmp_path):
    from gi import _core
    from gi.study import check_runs, run_study, table_runs
    table = {"spp": 2, "runs": [{"label": "PT depth 2", "integrator": "path", "params": {"pathDepth": 2}},
                                {"integrator": "direct", "spp": 3}]}
    runs = table_runs(table)
    check_runs(runs, _core.integrators())
    study = run_study(cornell, tiny_study["reference"], runs, tmp_path, log=lambda line: None)
    rows = {row["label"]: row for row in study.rows[1:]}
    assert rows["PT depth 2"]["spp"] == 2 and json.loads(rows["PT depth 2"]["params"]) == {"pathDepth": 2}
    assert rows['direct {}']["spp"] == 3 and rows['direct {}']["budget_seconds"] == ""
    assert "Fixed parameters" in (tmp_path / "report.md").read_text()


@pytest.mark.parametrize("entry, message", [
    ({"integrator": "noSuchIntegrator"}, "unknown integrator"),
    ({"integrator": "path", "params": {"noSuchParam": 1}}, "has no parameter 'noSuchParam'"),
    ({"integrator": "path", "params": {"pathDepth": -1}}, "outside"),
])
def test_params_table_errors_are_reported(entry, message):
    from gi import _core
    from gi.study import check_runs, table_runs
    with pytest.raises(ValueError, match=message):
        check_runs(table_runs([entry]), _core.integrators())


# -- gi reference --------------------------------------------------------------------------------

def test_reference_writes_spp_time_and_error_estimate(cornell, tmp_path):
    out = tmp_path / "ref16.exr"
    proc = run_gi("reference", cornell, "-o", out, "--resolution", 16, 16, "--max-seconds", 0.3)
    pixels, meta = read_meta(out)
    assert pixels.shape == (16, 16, 3) and np.isfinite(pixels).all() and pixels.mean() > 0.01
    assert meta["gi:non_finite_samples"] == "0"  # the film zeroes bad samples: finite pixels alone prove nothing
    assert meta["gi:integrator"] == "path" and int(meta["gi:spp"]) > 0 and int(meta["gi:batches"]) >= 2
    error, seconds = float(meta["gi:relative_standard_error"]), float(meta["gi:seconds"])
    assert 0 < error < 1 and math.isfinite(float(meta["gi:pixel_relative_standard_error"]))
    if meta["gi:stopped_by"] == "target":
        assert error <= 0.002
    else:
        assert meta["gi:stopped_by"] == "time" and 0.3 <= seconds < 3.0
    assert f"{meta['gi:spp']} spp" in proc.stdout


def test_reference_stops_once_the_target_is_reached(cornell, tmp_path):
    from gi.reference import MIN_BATCHES
    out = tmp_path / "coarse.exr"
    run_gi("reference", cornell, "-o", out, "--resolution", 16, 16, "--max-seconds", 60, "--target-error", 0.5)
    _, meta = read_meta(out)
    assert meta["gi:stopped_by"] == "target" and int(meta["gi:batches"]) == MIN_BATCHES
    assert float(meta["gi:relative_standard_error"]) <= 0.5 and float(meta["gi:seconds"]) < 30


OPEN_FLOOR = """#usda 1.0
(
    defaultPrim = "World"
    upAxis = "Y"
)
def Xform "World"
{
    def Mesh "Floor"
    {
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-4, 0, -4), (-4, 0, 4), (4, 0, 4), (4, 0, -4)]
        uniform token subdivisionScheme = "none"
    }
    def Mesh "Wall"
    {
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-4, 0, -1), (4, 0, -1), (4, 2, -1), (-4, 2, -1)]
        uniform token subdivisionScheme = "none"
    }
    def DistantLight "Sun"
    {
        float inputs:angle = 0.53
        float inputs:intensity = 2
        bool inputs:normalize = 1
        float3 xformOp:rotateXYZ = (-50, 20, 0)
        uniform token[] xformOpOrder = ["xformOp:rotateXYZ"]
    }
    def DomeLight "Sky"
    {
        color3f inputs:color = (0.5, 0.6, 0.9)
    }
    def Camera "Camera"
    {
        float2 clippingRange = (0.01, 100)
        float3 xformOp:rotateXYZ = (-35, 0, 0)
        double3 xformOp:translate = (0, 2.5, 3)
        uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateXYZ"]
    }
}
"""


def test_reference_with_the_sun_by_photons_is_the_sum_of_its_lights(tmp_path):
    """--sun-by-photons: the path tracer without the distant light plus the photon map of it alone.
    With nothing between the sun and the floor both halves converge, so the sum must be the plain
    path-traced reference, and the sky half alone must be darker by the sun's share."""
    scene = tmp_path / "open_floor.usda"
    scene.write_text(OPEN_FLOOR)
    plain, split = tmp_path / "plain.exr", tmp_path / "split.exr"
    common = ["--resolution", 24, 18, "--target-error", 1e-6, "--camera", "/World/Camera"]
    run_gi("reference", scene, "-o", plain, "--max-seconds", 3, *common)
    proc = run_gi("reference", scene, "-o", split, "--max-seconds", 6, "--sun-by-photons", *common)
    a, _ = read_meta(plain)
    b, meta = read_meta(split)
    assert meta["gi:sun"].startswith("progressivePhotonMap of the 1 distant light(s) alone") and "the sun by" in proc.stdout
    assert np.isfinite(b).all() and abs(b.mean() / a.mean() - 1) < 0.01
    from gi.reference import stage_with_suns
    stage, suns = stage_with_suns(scene, keep=False)
    assert suns == 1 and not stage.GetPrimAtPath("/World/Sun").IsActive() and stage.GetPrimAtPath("/World/Sky").IsActive()


# -- the reference's statistics ------------------------------------------------------------------

def test_weighted_standard_error_of_two_batches():
    from gi.reference import weighted_standard_error
    # Batches 1 and 3 with one sample each: mean 2, spread 2 over 1 degree of freedom, SE sqrt(2/2).
    mean, error = weighted_standard_error(1.0 + 3.0, 1.0 + 9.0, 2, 2)
    assert mean == 2.0 and error == pytest.approx(1.0)
    assert math.isinf(weighted_standard_error(1.0, 1.0, 1, 1)[1])


def test_weighted_spread_estimates_the_per_sample_variance_without_bias():
    from gi.reference import weighted_standard_error
    rng = np.random.default_rng(7)
    spp = np.array([1, 2, 4, 8, 16, 16])           # batches of unequal weight, as a reference makes
    sigma, trials = 0.5, 20000
    means = rng.normal(3.0, sigma / np.sqrt(spp), size=(trials, spp.size))
    total = spp.sum()
    _, error = weighted_standard_error((spp * means).sum(1), (spp * means ** 2).sum(1), total, spp.size)
    # error^2 = s^2 / N, and s^2 is unbiased for sigma^2.
    assert np.mean(error ** 2 * total) == pytest.approx(sigma ** 2, rel=0.03)


def test_accumulated_image_is_the_spp_weighted_mean():
    from gi.reference import BatchAccumulator
    accumulator = BatchAccumulator()
    accumulator.add(np.full((2, 2, 3), 1.0, np.float32), 1)
    accumulator.add(np.full((2, 2, 3), 4.0, np.float32), 3)
    assert accumulator.samples == 4 and accumulator.batches == 2
    np.testing.assert_allclose(accumulator.image(), 3.25)
    # Batch means 1 and 4, weights 1 and 3: s^2 = (1 * 2.25^2 + 3 * 0.75^2) / 1, SE = sqrt(s^2 / 4), over 3.25.
    expected = math.sqrt((2.25 ** 2 + 3 * 0.75 ** 2) / 4) / 3.25
    assert accumulator.relative_standard_error() == pytest.approx(expected)


def test_fireflies_are_counted_against_the_reference(tiny_study):
    """fireflies: whole pixels above 10x the reference's local luminance (metrics.firefly_count);
    none in the reference against itself."""
    assert float(tiny_study["rows"][0]["fireflies"]) == 0
    for row in run_rows(tiny_study):
        count = float(row["fireflies"])
        assert 0 <= count <= SIZE[0] * SIZE[1] and count.is_integer()


def test_equal_time_runs_keep_their_budget_and_the_report_says_so(tiny_study):
    """Each run's seconds lie within 5% + 0.2 s of its budget (issue 16's bound), and the
    equal-time tables show budget, measured and wall seconds, and the machine."""
    for row in rendered_rows(tiny_study):  # a denoised row adds its denoising time (test below)
        budget = float(row["budget_seconds"])
        assert abs(float(row["seconds"]) - budget) <= 0.05 * budget + 0.2, row
    text = (tiny_study["out"] / "report.md").read_text()
    assert "| budget s | time s | wall s |" in text
    for budget in BUDGETS:
        assert f"### Equal time: {budget:g} s (measured " in text
    assert "Measured on " in text and "render threads" in text and "one run of each technique" in text


# -- denoised rows -------------------------------------------------------------------------------

def test_denoised_rows_are_the_same_renders_denoised(tiny_study):
    """Each path run has a '+ denoise' row: the same render (spp, raw colour kept in its EXR), its time
    the render's plus the denoising's, and its errors those of the denoised image. Whether denoising
    lowers FLIP is test_denoise's (at 16 spp, 128x128): in this 32x32 study a quiet machine renders
    enough samples in 0.6 s that the filter's blur can cost as much as it removes (measured: FLIP
    0.0451 denoised against 0.0449 raw)."""
    from gi import metrics
    if not oidn_installed():
        pytest.skip("Open Image Denoise is not installed")
    from gi.study import slug
    rows = {row["label"]: row for row in run_rows(tiny_study)}
    for budget in BUDGETS:
        raw, denoised = rows[f"path {budget:g}s"], rows[f"path {budget:g}s + denoise"]
        assert denoised["integrator"] == "path + denoise" and denoised["spp"] == raw["spp"]
        assert raw["denoise_seconds"] == "" and float(denoised["denoise_seconds"]) > 0
        assert float(denoised["seconds"]) == pytest.approx(float(raw["seconds"]) + float(denoised["denoise_seconds"]))
        raw_pixels, _ = read_meta(tiny_study["out"] / "runs" / f"{slug(raw['label'])}.exr")
        pixels, meta = read_meta(tiny_study["out"] / "runs" / f"{slug(denoised['label'])}.exr")
        channels = meta["channels"]
        noisy = pixels[..., [channels.index(c) for c in ("noisy.R", "noisy.G", "noisy.B")]]
        np.testing.assert_array_equal(noisy, raw_pixels[..., :3])
        assert meta["gi:denoised"].startswith("Open Image Denoise ")
        # The row's FLIP is the denoised image's (R, G, B), not the raw one's.
        reference, _ = read_meta(tiny_study["reference"])
        assert float(denoised["flip"]) == pytest.approx(metrics.flip(pixels[..., :3], reference[..., :3]), rel=1e-6)
        assert not np.array_equal(pixels[..., :3], noisy)
    report = (tiny_study["out"] / "report.md").read_text()
    assert "| path + denoise |" in report and "path 0.3s + denoise" in report


def test_study_denoise_choice(tiny_study, cornell, tmp_path, monkeypatch):
    common = ("study", cornell, "--reference", tiny_study["reference"], "--integrators", "direct", "--budgets",
              "0.1", "--resolution", *SIZE)
    proc = run_gi(*common, "--denoise", "path", "-o", tmp_path / "a", check=False)
    assert proc.returncode == 2 and "--denoise path: path is not among the study's integrators" in proc.stderr
    run_gi(*common, "--denoise", "none", "-o", tmp_path / "b")
    with open(tmp_path / "b" / "results.csv", newline="") as stream:
        assert [row["integrator"] for row in csv.DictReader(stream)] == ["path", "direct"]  # reference, run
    # Without Open Image Denoise: the default leaves the denoised rows out with a warning, a list is an error.
    monkeypatch.setenv("GI_OIDN_LIBRARY", str(tmp_path / "nowhere"))
    proc = run_gi(*common[:5], "path", *common[6:], "-o", tmp_path / "c")
    assert "gi: warning: no denoised rows: denoising needs Intel Open Image Denoise 2.x" in proc.stderr
    with open(tmp_path / "c" / "results.csv", newline="") as stream:
        assert all(not row["label"].endswith("+ denoise") for row in csv.DictReader(stream))
    proc = run_gi(*common[:5], "path", *common[6:], "--denoise", "path", "-o", tmp_path / "d", check=False)
    assert proc.returncode == 2 and "pip install pyoidn" in proc.stderr
