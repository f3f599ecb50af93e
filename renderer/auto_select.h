// Automatic choice of technique (integrator "auto"), which the thesis left as future work: short
// pilot renders of every global-illumination technique, at a reduced resolution, estimate on this
// scene each one's noise (two seeds against each other) and bias (against the consistent
// techniques' pilots), predict each one's error at the render's time budget, and the renderer then
// renders with the technique predicted best.
//
// Pilots are the final render in miniature: about kAutoPilotPixels pixels, the same camera, and
// photon counts scaled with the pixel count (the same photons per pixel footprint).
// The path tracer and the progressive photon map (whose photon maps belong to sample
// indices) render two seeds; the other techniques preprocess once (their cache or photon map) and
// render two disjoint ranges of sample indices, so the two images differ by camera-sample noise
// only, and the error of the cache or map they share counts as their bias: at fixed parameters
// no number of camera samples removes it.
//
// The prediction, on 8-bit sRGB codes (the thesis's RMSE), per technique with pilot images a, b:
//   noise  v = mean((a - b)^2) / 2                    one image's camera-sample variance
//   error  e = mean(((a + b) / 2 - R)^2) - Var(R)     the two images' mean's squared error, where R
//                                                     is the inverse-variance mean of the consistent
//                                                     techniques' pilots (path, progressivePhotonMap)
//   bias   b2 = max(0, e - v / 2)
//   MSE(T) = b2 * r + v * r for the consistent techniques (for the path tracer a missed bright
//            path is noise, not bias, and the progressive photon map's radii shrink), and
//            b2 + v * r for the others, where r is the pilot's render seconds per pixel over the
//            final render's (its budget less its preprocessing, the pilot's grown with the pixel
//            count and at most kPreprocessShare of the budget). A cache's pilot had less
//            preprocessing than the final render will have, so this errs on its pessimistic side.
// A technique other than the path tracer is chosen only when its predicted MSE is below
// kAutoMargin of the path tracer's, so an uncertain prediction falls back on the unbiased one.
#pragma once
#include <atomic>
#include <string>
#include <vector>

#include "camera.h"
#include "scene.h"

namespace gi {

struct RenderSettings;

inline constexpr const char* kAutoIntegrator = "auto";
// The techniques the pilots compare (ray tracing, "direct", misses indirect light by design).
// A technique whose pilot cannot render a whole image in its share of the pilot time (its
// preprocessing alone takes longer) is left out of the choice, and the log says so.
const std::vector<std::string>& autoCandidates();
// Another technique must predict at most this share of the path tracer's MSE to be chosen.
inline constexpr double kAutoMargin = 0.8;
// Pilot images have about this many pixels (fewer if the render itself is smaller).
inline constexpr int kAutoPilotPixels = 2048;

struct AutoPrediction {
    std::string integrator;
    bool consistent = false;
    bool complete = false;        // its pilots each rendered a whole image in their time
    double renderSeconds = 0, preprocessSeconds = 0;  // of one pilot
    double noise = 0, bias = 0;   // v and b2 above, sRGB codes squared
    double predictedRmse = 0;     // sqrt of the predicted MSE at the budget, sRGB codes
};

struct AutoChoice {
    std::string integrator;       // the technique chosen
    double budgetSeconds = 0;     // what the prediction was for
    double pilotSeconds = 0;      // wall time of all pilots
    int pilotWidth = 0, pilotHeight = 0;
    std::vector<AutoPrediction> predictions;
    bool cancelled = false;
    std::string summary() const;  // one line: the choice and every prediction
};

// A technique's two pilot images (sRGB codes, 0..255 unquantised), or none (incomplete).
struct AutoPilot {
    std::string integrator;
    std::vector<double> codes[2];
    double renderSeconds = 0;      // of one image
    double preprocessSeconds = 0;  // of the pilot's preprocessing (shared by its two images)
    bool complete = false;
};

// The prediction above from the pilots (each `pilotPixels` pixels) for a render of `pixels`
// pixels with `budgetSeconds`; the choice among the complete pilots ("path" if none is).
AutoChoice predictFromPilots(const std::vector<AutoPilot>& pilots, double pilotPixels, double pixels,
                             double budgetSeconds);

// Renders the pilots (`pilotSeconds` of wall time in all, shared equally) and predicts each
// technique's error after `budgetSeconds` more of rendering at `settings`' resolution. The
// pilots take `settings`' seed + 1, + 2, ...; its preset applies to each technique.
AutoChoice chooseIntegrator(const Scene& scene, const RenderSettings& settings, const CameraDesc& camera,
                            double budgetSeconds, double pilotSeconds, const std::atomic<bool>* cancel);

}  // namespace gi
