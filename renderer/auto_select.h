// Automatic choice of technique (integrator "auto"), which the thesis left as future work: short
// pilot renders of every global-illumination technique, on a few tiles of the image, estimate on this
// scene each one's noise (its batches against each other) and bias (against the consistent
// techniques' pilots), predict each one's error at the render's time budget, and the renderer then
// renders with the technique predicted best. auto_pilots.cpp renders the pilots, auto_select.cpp
// makes the prediction.
//
// Pilots are samples of the final render: about kAutoPilotPixels of its own pixels in
// kAutoPilotTiles tiles (pilotMosaic), the same camera, and photon counts scaled with the pixel
// count (photon tracing costs as much per pixel as in the render). Each technique preprocesses and
// renders up to kAutoPilotBatches batches in equal shares of the time left (each at least one
// sample per pixel, so an expensive technique makes fewer), each an image of its own seed's samples
// from index 0, so that the batches are independent and their spread is their mean's noise: batches
// of consecutive indices of one seed are stratified against each other (Owen-scrambled Sobol
// points), so their mean had less noise than their spread said, and what bias there was hid under
// it (Sibenik with portals: the photon cache's single-cache pilots, two or three batches of one
// sample, measured 46-66 codes squared from R where their spread said 75-96 of noise, so no bias,
// and predicted 0.5-1.0 codes for 1.8 reached; bench runs in docs/auto.md). A technique with a cache
// (irradiance records, photon maps) preprocesses twice, with two seeds, and renders half its
// batches from each: the two caches' difference is the cache's own noise, which shrinks in the
// render (records gain paths with the camera's samples, photon maps have the render's photons);
// what both share is bias, which no number of camera samples removes. Where two caches cannot each
// make two batches in the pilot's time, one cache takes all of it.
//
// The prediction is of the RMSE on 8-bit sRGB codes f (the thesis's metric), and its noise part is
// made from linear batch values, because f compresses highlights: in a pilot of few samples a
// firefly (a caustic through glass) is clamped to code 255, so noise measured on pilot codes and
// scaled by 1/time underestimates the final render's (measured on the Cornell box: 4.1 predicted,
// 21 reached, in codes squared). Per pixel value, with batches B_k (K of them), M their mean,
// c_k the mean of the values in its 3x3 pixel window over all batches but B_k itself (independent
// of B_k, so a firefly in B_k does not move the point f is taken at for it as it moves M; and
// spatially pooled, since f is steepest near 0 and a noisy centre makes (f')^2 too large on
// average; but m_k below where the window's mean clips at code 255 and m_k does not: beside a
// light the window would hide the pixel's noise), d_k = (B_k - m_k) sqrt((K - 1) / K) with m_k
// the mean of the pixel's other batches (one
// batch's deviation: Var(B_k - m_k) is K / (K - 1) times one batch's variance), an image of 1/q
// batches' samples has, in codes squared,
//   noise(q) = min(mean_k (f(c_k + q d_k) - f(c_k))^2 / q, max(f(M), 255 - f(M))^2)
// (for small d this is f'(c)^2 Var(B) q, the delta method; a firefly counts with its full linear
// size scaled to the render's samples and clamped as the render's codes will clamp it; a pixel's
// error is at most the distance to code 0 or 255). Measured at 160x120 (noise of a render against
// a second seed's, and the prediction from batches of 8 other seeds), in codes squared:
//   Cornell box, path tracer, 256 samples: 21.2 reached; predicted from 8 batches of 16 samples
//   23.2 (of 2 samples: 29.1); the old estimate on pilot codes: 4.1;
//   Sponza, path tracer, 64 samples: 191 reached; predicted from 8 batches of 4 samples 175 (the
//   old estimate 108; the centre without the window, c_k = m_k: 306).
// Then, per technique,
//   error  e = mean((f(M) - R)^2) - Var(R)            the pilot's mean's squared error, where R is
//                                                     the inverse-variance mean of the consistent
//                                                     techniques' pilots' codes f (path,
//                                                     progressivePhotonMap; see below)
//   cache  c2 = max(0, mean((f(M_1) - f(M_2))^2) - v_D) / 2, with M_1, M_2 the two caches' means
//               over their P paired batches (the second cache renders the first's batches pass
//               for pass from the same camera samples, with its own cache seed), v_D the noise
//               of their difference: the smaller of the pairs' differences' noise(1 / P) and
//               noise_1(1 / P) + noise_2(1 / P) (noise(q) from each batch's deviation from its
//               own cache's others); 0 with one cache
//   bias   b2 = max(0, e - noise(1 / K) - s - c2 / 2)   (s = w_1 w_2 (v_1 + v_2 - v_D), what the
//                                                     caches' shared samples add to the mean's
//                                                     noise; e, Var(R), these noises and c2 over all values
//                                                     but the kBiasTrim share where the path
//                                                     tracer's batches spread most: there R's
//                                                     error is heavy-tailed; and each on the
//                                                     means of kBiasBlock-square blocks of those
//                                                     values: R's noise, apart from pixel to pixel,
//                                                     falls there by the block's values, a bias
//                                                     smooth over the block does not)
//   MSE(T) = b2 * min(1, K r) + noise(r) for the path tracer (a missed bright path is noise, not
//            bias), where r is one batch's mean samples over the final render's: its budget
//            (less its preprocessing, the pilot's grown with the pixel count and at most
//            kPreprocessShare of the budget) at the pilot's rates with every thread busy: its
//            samples' own, its records' start-up and their refinement (AutoPilot's rates;
//            batches are time slices, so their samples differ: the mean images weigh them by
//            their samples, and noise(q) scales each batch's deviation to the mean batch's
//            samples);
//            b2 * (h(N) / h(n))^2 + noise_t(r) + noise(r g(N) / g(n)) - noise_t(r g(N) / g(n))
//            for the progressive photon map (its b2 its blur against the path tracer, scaled
//            from the pilot's wider radii), n a batch's samples (each took indices from 0) and
//            N = n / r the render's, h and g the mean of s_i and 1 / s_i over their sample
//            indices, s_i = (r_i / r_1)^2: its blur goes as r^2, and each sample's photon noise
//            as 1 / r^2, so that part falls as N^-alpha, not N^-1 (on the Cornell box at 60 s
//            1 / N predicted 0.55 for 0.9 reached); noise_t is its ray-traced part's alone
//            (its pilot's rayTracedBatches, moved to its batches' mean so that f' is the
//            image's), which the radii do not grow (on Sibenik with portals at 60 s, all of a
//            sample's noise grown as the photons' predicted 0.82-0.86 for 0.41 reached);
//            b2 + c2 * share + noise(r) for the others, share the larger of the pilot's records'
//            mean paths over the render's (records refined as the render goes on: their paths
//            grow more slowly than the samples where the render keeps making records; 1 if not
//            refined; recordPathsShare in auto_select.cpp) and the pilot's photons over the
//            render's (on the Cornell box at 60 s the irradiance cache's pilot error, taken as bias
//            alone, predicted 2.5 for 0.8 reached: refined records keep converging; with the
//            cache's noise apart, 1.6 to 1.8, still pessimistic).
// A photon technique's second cache traces more photons than the first where a third of its time
// allows 2x or more (the pilots' photons, scaled with their pixels, are 1/18 of the render's at
// 160x120): both its cache noise and each camera sample's noise fall with the photons, as x, the
// render's photons over a cache's. Then c2 above is the first cache's (the difference's
// x_1 / (x_1 + x_2)), the render's c2 x_1-th of it, the mean's w_1^2 c_2 + w_2^2 c_2 x_2 / x_1
// (w the caches' shares of the samples), and its noise(r) a + b x at x = 1 through each cache's
// own noise at the render's samples (a >= 0). On the Cornell box at 37x28 (one photon map, the
// samples' noise x samples from a quarter of the samples against all, 3 seeds;
// bench/pilot_accuracy.py), final gathering's was 157, 97 and 73 at 27,000 (the pilots'), 125,000
// and 500,000 photons (the render's), the photon cache's 207, 86 and 33: a + b x through the
// first two gives 85 and 61 at the render's photons, where the pilots' 27,000 alone gave 157 and
// 207. Over 6 runs of the pilots at 60 s final gathering's
// predicted sample noise went from 0.73 to 1.24 (pooled) to 0.43 to 0.86 (this law), for about
// 0.33 reached: the caches' 4 batches each are noisy inputs.
// R weighs the progressive photon map's pilot by its noise and its blur (its difference from the
// path tracer's, less both noises), unless its typical batch (the median of the batches' means)
// is brighter than the path tracer's by more than 4 standard errors and 2%, when the path tracer
// misses light (a sun through glass) and the blur, which keeps the image's mean, is not counted:
// its pilot's first radii, wide and (with its photons scaled with the pixels) wider in the
// world, blur it by 4 to 5 codes RMSE on the Cornell box (the caches' whole error).
// A technique other than the path tracer is chosen only when its predicted MSE is below
// kAutoMargin of the path tracer's, so an uncertain prediction falls back on the unbiased one.
#pragma once
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "camera.h"
#include "scene.h"

namespace gi {

struct RenderSettings;

inline constexpr const char* kAutoIntegrator = "auto";
// The techniques the pilots compare (ray tracing, "direct", misses indirect light by design).
// A technique whose pilot cannot render two batches in its share of the pilot time (its
// preprocessing alone takes most of it) is left out of the choice, and the log says so.
const std::vector<std::string>& autoCandidates();
// The techniques whose error falls to zero with time (the path tracer, the progressive photon
// map): the pilots' reference is made of theirs.
inline bool isConsistentTechnique(const std::string& integrator) {
    return integrator == "path" || integrator == "progressivePhotonMap";
}
// Another technique must predict at most this share of the path tracer's MSE to be chosen.
inline constexpr double kAutoMargin = 0.8;
// Pilot images have about this many pixels (fewer if the render itself is smaller): few enough
// that, in 0.1 of a 10 s budget on 2 cores, the caches' pilots preprocess and still render
// batches (at 2048 pixels the irradiance caches and the photon map's final gathering on the
// Cornell box made one batch each).
inline constexpr int kAutoPilotPixels = 1024;
// The pilots' pixels are the render's own (records spaced, photon discs and a sample's cost as
// the render's) in about this many square tiles spread evenly over the image, kAutoPilotPixels
// in all: pilots once had the render's camera at about kAutoPilotPixels coarse pixels, where a
// record cache's bias, its records spaced in pixels, was 50 times the render's (Sibenik under its
// sky, 37x28 against 160x120) and its sample cost twice the render's. A render of at most twice
// kAutoPilotPixels is its own pilot.
inline constexpr int kAutoPilotTiles = 9;
// The tiles of a width x height render that its pilots render (empty: the whole image).
PixelMosaic pilotMosaic(int width, int height);
// Batches per pilot: the more, the less noisy the others' mean below (with the centre taken
// without the window, Sponza's prediction was 486, 366 and 306 with 4, 6 and 8 batches for a true
// 191); few enough that a batch of an expensive technique still takes a sample in every pixel.
inline constexpr int kAutoPilotBatches = 8;
// A photon technique's second cache may spend this share of its time tracing more photons.
inline constexpr double kPhotonGrowthPreprocessShare = 1.0 / 3;

struct AutoPrediction {
    std::string integrator;
    bool consistent = false;
    bool complete = false;        // its pilot rendered at least two whole batches in its time
    int batches = 0;              // the batches it rendered
    double pilotSeconds = 0;      // its share of the pilot time
    double preprocessSeconds = 0;  // of the pilot
    double noise = 0, bias = 0;   // noise(1) (one batch's) and b2 above, sRGB codes squared
    double cacheNoise = 0;        // c2 above: one cache's noise, sRGB codes squared
    // b2's standard error, for a technique that keeps its bias: the jackknife over its pilot's
    // batches (pairs of batches with two caches); 0 where not known (fewer than three). Logged, not
    // used in the choice: taken at b2 + z se, the choice lost more at 10 s than it gained at 60 s
    // (docs/auto.md).
    double biasError = 0;
    double predictedRmse = 0;     // sqrt of the predicted MSE at the budget, sRGB codes
    // The predicted MSE's parts at the budget (sRGB codes squared; they sum to predictedRmse^2):
    // the bias left, the cache's own noise left, the camera samples' noise.
    double predictedBias = 0, predictedCacheNoise = 0, predictedSampleNoise = 0;
    // The samples per pixel it would render in the budget, at its pilot's rates (0: not known).
    double predictedSamples = 0;
};

struct AutoChoice {
    std::string integrator;       // the technique chosen
    double budgetSeconds = 0;     // what the prediction was for
    double pilotSeconds = 0;      // wall time of all pilots
    int pilotTile = 0, pilotTiles = 0;  // the pilots' tiles of the image (0: the whole image)
    std::vector<AutoPrediction> predictions;
    bool cancelled = false;
    bool kept = false;  // an earlier render's choice, taken without pilots (RenderSettings::keptAutoChoice)
    std::string summary() const;  // one line: the choice and every prediction
};

// A technique's pilot: its batches (linear RGB, every one the same size), or too few (incomplete).
struct AutoPilot {
    std::string integrator;
    int width = 0, height = 0;
    // Its pixels are square tiles of this side, laid side by side (0: one image; pilotMosaic).
    int tile = 0;
    std::vector<std::vector<float>> batches;  // each width * height * 3
    double seconds = 0;            // its share of the pilot time
    double preprocessSeconds = 0;  // of the pilot's preprocessing (shared by its batches)
    bool complete = false;         // at least two batches
    // The progressive photon map's alpha: its radii shrink with the sample index (0 otherwise);
    // each batch took indices from 0 on.
    double radiusAlpha = 0;
    // Its ray-traced part alone (no photons: emission, direct light, specular and glossy paths),
    // batches of the same seeds in a share of its time, and their samples per pixel; empty where
    // not measured. Its noise does not grow as the radii shrink.
    std::vector<std::vector<float>> rayTracedBatches;
    std::vector<double> rayTracedBatchSamples;
    // Two caches (records or photon maps, two seeds): batches [0, firstCacheBatches) used the
    // first, the others the second; 0: one cache (or none).
    int firstCacheBatches = 0;
    // Each batch's samples per pixel (a pass the deadline cut counts with the pixels it
    // finished), and the seconds a pixel's sample takes with every thread busy, past the cache's
    // start-up (records made where pixels first need them): its batches' thread-seconds in their
    // tiles, less the start-up's, over the threads, plus its passes' setup (a progressive photon
    // map's photons) unless that is a record refinement (below). Not the batches' wall time: a
    // pilot's passes are small, and their threads' idle ends made a sample look 1.3 times as dear
    // as in the render for the path tracer's batches of 8 samples, and 2-3 times for a cache's
    // batches of one (Sponza at 10 s: the irradiance cache predicted at 116-223 samples per pixel
    // for 390-459 reached; its pilot's thread-time, 0.92 us a sample, is the render's, 0.93).
    std::vector<double> batchSamples;
    double steadySecondsPerSample = 0;
    // Of its first cache's batches' time (thread-seconds over the threads), what went on records
    // made where no record covered a sample: a start-up the render pays per pixel as the pilot
    // did. It goes on as the samples land where no record is (Sponza's irradiance cache made
    // 2.25 thread-seconds of them in a 9 s render, 0.62 in its first second), about as the log of
    // the samples per pixel: `startupGrowthSeconds` more per unit of ln(samples) past
    // `startupSamples`, from the first cache's batches after its first (on Sponza 2.2 predicted
    // for that render). 0: a start-up once, as the pilot's.
    double startupSeconds = 0, startupGrowthSeconds = 0, startupSamples = 0;
    // Refined records (refineRecords): the render refines them until their rays match its
    // passes' (record_refinement.h), so past the fill's rays every ray a pass traces, records it
    // makes included, costs a record ray more. Per pixel sample its passes trace
    // `steadyRaysPerSample` rays besides the records they make; a record ray takes
    // `recordRaySeconds` (with every thread busy, from its start-up records); the fill traced
    // `fillRays`. On Sponza at 9 s the refinement was 6.7 of the irradiance cache's 17 render
    // thread-seconds, and the pilots' batches are too short to reach it. 0: not refined.
    double steadyRaysPerSample = 0, recordRaySeconds = 0, fillRays = 0;
    double photonShare = 0;       // its photon map's photons over the render's (0: no photon map)
    // The second cache's photons over the render's, where it traced more than the first (0: as
    // many, or not known: its preprocessing was cut short).
    double secondPhotonShare = 0;
    bool records = false;         // irradiance records...
    bool refinesRecords = false;  // ... refined between passes by as many paths as the camera traced
    // Refined records: the first cache after its batches, from which the render's records' paths
    // are predicted (0: not known; the cache's noise then falls with the camera's samples).
    double recordPaths = 0;        // mean paths of its path-traced records
    double recordsPerPixel = 0;    // its records over the pilot's pixels
    double recordGrowth = 0;       // its records grew as (samples per pixel)^recordGrowth over its batches
    double recordRaysPerPath = 0;  // its records' rays over their paths
    double passRaysPerSample = 0;  // rays its passes traced per pixel sample (records they made included)
    double cacheSamples = 0;       // samples per pixel its batches took
};

// noise(q) above: the mean squared error, in sRGB codes, of an image with 1/q times one of
// the pilot's batches' samples (q = 1: one batch's noise).
// Over the values `kept` marks, where given (a bias is measured on such values).
double predictedNoise(const AutoPilot& pilot, double q, const std::vector<uint8_t>* kept = nullptr);
// The share of values a bias is not measured on: those where the path tracer's pilot spreads most.
inline constexpr double kBiasTrim = 0.01;
// A bias is measured on the mean of blocks of kBiasBlock x kBiasBlock values (one channel, within a
// tile): R's noise, mostly the path tracer's pilot, is apart from pixel to pixel and falls in a
// block's mean as its values, while a cache's bias is smooth over a few pixels (its records).
inline constexpr int kBiasBlock = 2;
// The values of a pilot's layout (width, height, tile) in blocks of side x side within each tile,
// those `kept` marks (every one without it): `of[i]` the block of value i, -1 if not kept.
struct BiasBlocks {
    std::vector<int> of;
    int count = 0;
};
BiasBlocks biasBlocks(const AutoPilot& layout, const std::vector<uint8_t>* kept, int side);
// noise(q) of the blocks' means: each batch's deviations averaged over a block before they are
// squared, so that what moves a block's values together (a record) counts whole; each block weighs
// as its values. With blocks of one value, predictedNoise over those values.
double predictedNoise(const AutoPilot& pilot, const BiasBlocks& blocks, double q);

// The prediction above from the pilots (each `pilotPixels` pixels) for a render of `pixels`
// pixels with `budgetSeconds`; the choice among the complete pilots ("path" if none is). Biases
// are measured in blocks of `biasBlock` values a side (1: per value).
AutoChoice predictFromPilots(const std::vector<AutoPilot>& pilots, double pilotPixels, double pixels,
                             double budgetSeconds, int biasBlock = kBiasBlock);

// Renders the pilots (`pilotSeconds` of wall time in all, shared equally) and predicts each
// technique's error after `budgetSeconds` more of rendering at `settings`' resolution. The
// pilots take `settings`' seed + 1, + 2, ...; its preset applies to each technique.
AutoChoice chooseIntegrator(const Scene& scene, const RenderSettings& settings, const CameraDesc& camera,
                            double budgetSeconds, double pilotSeconds, const std::atomic<bool>* cancel);

}  // namespace gi
