"""testusdview script for bench/hydra.py --usdview: the render usdview starts when it opens a scene
with Gi (its default settings, the camera named on the command line), left alone until its first
full pass is in. Writes GI_USDVIEW_OUT/first_pass.json: the viewport's size and hdGi's render stats
at that moment (scene build, first pixels and first pass, each in seconds from the render's start).
usdview resizes its viewport after its first draw, which restarts the render (the scene is kept):
the stats when the script starts are that first render's, published when it stopped, and its
seconds are given as "restarted_render_seconds".
    testusdview --testScript usdview_first_pass.py --renderer Gi --camera CAMERA SCENE"""
import json
import os
import time
from pathlib import Path

from pxr.Usdviewq.qt import QtWidgets


def testUsdviewInputFunction(app):
    view = app._stageView
    start = time.monotonic()
    stats = dict(view._renderer.GetRenderStats())
    restarted = float(stats.get("renderSeconds", 0)) if float(stats.get("firstPassSeconds", 0)) == 0 else 0.0
    while time.monotonic() - start < 300:
        QtWidgets.QApplication.processEvents()
        stats = dict(view._renderer.GetRenderStats())
        if float(stats.get("firstPassSeconds", 0)) > 0:
            break
        time.sleep(0.002)
    result = {"viewport": list(view.computeWindowSize()), "waited_seconds": time.monotonic() - start,
              "restarted_render_seconds": restarted,
              "stats": {str(k): v for k, v in stats.items() if isinstance(v, (bool, int, float, str))}}
    Path(os.environ["GI_USDVIEW_OUT"], "first_pass.json").write_text(json.dumps(result))
