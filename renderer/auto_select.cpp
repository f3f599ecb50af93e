#include "auto_select.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "integrators/progressive_photon_map.h"
#include "render.h"

namespace gi {

namespace {

double srgbCode(double linear) {
    double x = std::clamp(linear, 0.0, 1.0);
    double v = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return 255.0 * v;
}

// The per-pixel-value mean of images, weighted by their samples (`samples` empty: alike).
std::vector<double> meanImage(const std::vector<std::vector<float>>& images, const std::vector<double>& samples = {}) {
    std::vector<double> mean(images.empty() ? 0 : images[0].size(), 0.0);
    double weightSum = 0;
    for (size_t k = 0; k < images.size(); ++k) {
        const double w = samples.size() == images.size() ? samples[k] : 1.0;
        weightSum += w;
        for (size_t i = 0; i < mean.size(); ++i) mean[i] += w * images[k][i];
    }
    for (double& m : mean) m /= weightSum > 0 ? weightSum : 1.0;
    return mean;
}

// A pilot's batch weights for meanImage: its batches' samples [first, end), if it counts them.
std::vector<double> sampleWeights(const AutoPilot& pilot, size_t first, size_t end) {
    if (pilot.batchSamples.size() != pilot.batches.size()) return {};
    return std::vector<double>(pilot.batchSamples.begin() + long(first), pilot.batchSamples.begin() + long(end));
}

std::vector<double> srgbCodes(const std::vector<double>& linear) {
    std::vector<double> codes(linear.size());
    for (size_t i = 0; i < linear.size(); ++i) codes[i] = srgbCode(linear[i]);
    return codes;
}


// The mean over sample indices [first, end) of s_i^power, s_i = (r_i / r_1)^2 the progressive
// photon map's squared radius at index i: power 1 is how its blur (bias, as r^2) goes, power -1
// how its photon noise goes (a pass's variance, as 1 / r^2). A fractional end (a pilot batch's
// mean samples, a pass the deadline cut) counts its last index by its fraction: taken whole, a
// mean of 1.25 samples gave 1.76 at power -1 where one sample gives 1 (alpha 2/3). Exact
// over the first 4096 indices, then a midpoint rule (s_i is smooth there) so a long render costs
// no more.
double meanRadiusPower(double alpha, double first, double end, double power) {
    if (!(end > first)) return 1;
    auto term = [&](double i) {
        return std::pow(double(ProgressivePhotonMapIntegrator::radiusScale(uint32_t(i), float(alpha))), 2 * power);
    };
    constexpr int kExact = 4096;
    const double whole = std::floor(end - first);
    const double exactEnd = first + std::min(whole, double(kExact));
    double sum = 0;
    for (double i = first; i < exactEnd; ++i) sum += term(i);
    if (first + whole > exactEnd) {
        const double width = (first + whole - exactEnd) / kExact;
        for (int k = 0; k < kExact; ++k) sum += width * term(std::floor(exactEnd + (k + 0.5) * width));
    }
    sum += (end - first - whole) * term(first + whole);
    return sum / (end - first);
}

// A pilot's typical brightness: the median of its batches' mean values, and that median's
// variance from their spread (median absolute deviation). A light the path tracer finds about
// once in 10^5 bounces (a sun through glass) leaves most of its batches dark and one bright: in
// the glazed room at 128x96 seven batch means of 0.082-0.085 and one of 0.63, against the photon
// map's 0.139-0.144, whose mean 0.152 then hid the miss.
void typicalBrightness(const AutoPilot& pilot, double& median, double& varianceOfMedian) {
    std::vector<double> perBatch;
    for (const auto& batch : pilot.batches) {
        double sum = 0;
        for (float v : batch) sum += v;
        perBatch.push_back(sum / double(std::max<size_t>(1, batch.size())));
    }
    auto medianOf = [](std::vector<double> values) {
        const size_t half = values.size() / 2;
        std::nth_element(values.begin(), values.begin() + long(half), values.end());
        double m = values[half];
        if (values.size() % 2 == 0) m = 0.5 * (m + *std::max_element(values.begin(), values.begin() + long(half)));
        return m;
    };
    median = medianOf(perBatch);
    std::vector<double> deviations;
    for (double b : perBatch) deviations.push_back(std::fabs(b - median));
    // 1.4826 MAD is a normal spread's standard deviation; a median's variance is pi / 2 a mean's.
    const double sigma = 1.4826 * medianOf(deviations);
    varianceOfMedian = 0.5 * M_PI * sigma * sigma / double(perBatch.size());
}

// Over every value.
double meanSquaredDifference(const std::vector<double>& a, const std::vector<double>& b) {
    double sum = 0;
    for (size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
    return a.empty() ? 0 : sum / double(a.size());
}

// The blocks' mean differences squared, each weighed by its values (meanSquaredDifference with
// blocks of one value).
double meanSquaredDifference(const std::vector<double>& a, const std::vector<double>& b, const BiasBlocks& blocks) {
    std::vector<double> sum(size_t(blocks.count), 0.0), size(size_t(blocks.count), 0.0);
    for (size_t i = 0; i < a.size(); ++i)
        if (blocks.of[i] >= 0) sum[size_t(blocks.of[i])] += a[i] - b[i], size[size_t(blocks.of[i])] += 1;
    double total = 0, values = 0;
    for (size_t k = 0; k < sum.size(); ++k)
        if (size[k] > 0) total += sum[k] * sum[k] / size[k], values += size[k];
    return values > 0 ? total / values : 0;
}

// The values a bias is measured on: all but the kBiasTrim share where the path tracer's pilot
// batches spread most in codes (caustics, a light's neighbours). R is mostly that pilot, and its
// error there is heavy-tailed: on the Cornell box at 60 s the top 1% of values held 36-46% of each
// cache's squared difference from R, and the caches' bias estimates scattered from 0 to 6 codes
// squared between runs for about 0.3.
std::vector<uint8_t> valuesForBias(const AutoPilot* path, size_t n) {
    std::vector<uint8_t> kept(n, 1);
    if (!path || path->batches.size() < 2 || n == 0) return kept;
    std::vector<double> sum(n, 0.0), squares(n, 0.0);
    for (const auto& batch : path->batches)
        for (size_t i = 0; i < n; ++i) {
            const double code = srgbCode(batch[i]);
            sum[i] += code;
            squares[i] += code * code;
        }
    const double K = double(path->batches.size());
    std::vector<double> spread(n);
    for (size_t i = 0; i < n; ++i) spread[i] = squares[i] / K - (sum[i] / K) * (sum[i] / K);
    std::vector<double> sorted = spread;
    const size_t cut = std::min(n - 1, size_t(std::floor(double(n) * (1 - kBiasTrim))));
    std::nth_element(sorted.begin(), sorted.begin() + long(cut), sorted.end());
    const double threshold = sorted[cut];
    size_t left = 0;  // ties at the threshold stay, up to the share
    for (size_t i = 0; i < n; ++i)
        if (spread[i] > threshold || (spread[i] == threshold && ++left > n - cut)) kept[i] = 0;
    return kept;
}

// Whether a photon technique's second cache traced more photons than its first (the law a + b x).
bool hasPhotonLaw(const AutoPilot& pilot) {
    return pilot.firstCacheBatches > 0 && pilot.photonShare > 0 && pilot.secondPhotonShare > pilot.photonShare;
}

// Each cache's photons short of the render's, x_1 and x_2 (1 and 1 without that law).
std::pair<double, double> photonsShortOf(const AutoPilot& pilot) {
    return hasPhotonLaw(pilot) ? std::make_pair(1 / pilot.photonShare, 1 / pilot.secondPhotonShare)
                               : std::make_pair(1.0, 1.0);
}

// A pilot's batches' mean samples per pixel (0 without any).
double meanBatchSamples(const AutoPilot& pilot) {
    double mean = 0;
    for (double samples : pilot.batchSamples) mean += samples / double(pilot.batchSamples.size());
    return mean;
}

// The batches [first, end) of a pilot, as a pilot of one cache.
AutoPilot cachePilot(const AutoPilot& pilot, size_t first, size_t end) {
    AutoPilot part = pilot;
    part.batches.assign(pilot.batches.begin() + long(first), pilot.batches.begin() + long(end));
    part.batchSamples = pilot.batchSamples.size() == pilot.batches.size()
                            ? std::vector<double>(pilot.batchSamples.begin() + long(first),
                                                  pilot.batchSamples.begin() + long(end))
                            : std::vector<double>(part.batches.size(), 1.0);
    part.firstCacheBatches = 0;
    return part;
}

// The progressive photon map's ray-traced part (AutoPilot::rayTracedBatches) as a pilot of its
// own, each value moved by the technique's mean less the part's: its deviations, taken where f
// is as steep as in the image (the part alone is darker, and f steeper there).
AutoPilot rayTracedPart(const AutoPilot& pilot) {
    AutoPilot part = cachePilot(pilot, 0, pilot.batches.size());
    part.batches = pilot.rayTracedBatches;
    part.batchSamples = pilot.rayTracedBatchSamples;
    const std::vector<double> technique = meanImage(pilot.batches, sampleWeights(pilot, 0, pilot.batches.size())),
                              own = meanImage(part.batches, sampleWeights(part, 0, part.batches.size()));
    for (auto& batch : part.batches)
        for (size_t i = 0; i < batch.size(); ++i) batch[i] = float(batch[i] - own[i] + technique[i]);
    return part;
}

// Two caches' paired batches (the same camera samples, cache 1's k-th batch with cache 2's) as
// one pilot whose noise(q) is that of the caches' mean difference, in codes: batch k is the
// caches' mean image plus the k-th pair's difference from the pairs' mean difference.
AutoPilot pairedDifferences(const AutoPilot& first, const AutoPilot& second) {
    AutoPilot pairs = first;
    const size_t K = std::min(first.batches.size(), second.batches.size());
    const size_t n = first.batches.empty() ? 0 : first.batches[0].size();
    pairs.batches.assign(K, std::vector<float>(n));
    pairs.batchSamples.assign(K, 1.0);
    std::vector<double> mean(n, 0.0), meanDifference(n, 0.0);
    for (size_t k = 0; k < K; ++k)
        for (size_t i = 0; i < n; ++i) {
            mean[i] += (double(first.batches[k][i]) + second.batches[k][i]) / double(2 * K);
            meanDifference[i] += (double(first.batches[k][i]) - second.batches[k][i]) / double(K);
        }
    for (size_t k = 0; k < K; ++k)
        for (size_t i = 0; i < n; ++i)
            pairs.batches[k][i] =
                float(mean[i] + (double(first.batches[k][i]) - second.batches[k][i]) - meanDifference[i]);
    return pairs;
}

// The noise a + b x at x = 1 (the render's photons) through v1 at x1 and v2 at x2 < x1: no less
// than 1 / x falls (a >= 0), and v2 where more photons did not lower it.
double noiseAtTheRendersPhotons(double v1, double x1, double v2, double x2) {
    const double b = (v1 - v2) / (x1 - x2);
    if (!(b > 0)) return v2;
    const double a = v2 - b * x2;
    return a >= 0 ? a + b : v2 / x2;
}

// The pilot's refined records' mean paths over the render's, after `renderSamples` samples per
// pixel of `pixels`: a record's noise goes as 1 / its paths. The render refines its records until
// their rays match its passes' (record_refinement.h), so its records' paths are its passes' rays
// over its records, at the pilot's rays per record path; its records are the pilot's per pixel,
// grown with the samples as over the pilot's batches (new records where samples land uncovered).
// Measured with fixed sample counts (irradianceCache, 160x120, passes' rays as the stats give):
// Sponza's records grew 1.27-1.33x per 4x the samples from 4 to 4096 spp (5,258 to 19,520), so its
// records' paths grew 1.4-2.2x (108 at the fill, 392 at 256 spp, 1,585 at 4096), not 4x; the
// Cornell box's stayed at 1,506-1,528 and their paths grew 3.6-4.0x. Predicted from pilots at
// 60 s: Sponza 806-900 paths at 1,300-1,600 spp, the Cornell box 3,700-4,100 at 1,100-1,300 (about
// 7,000 reached: pessimistic). The parts are off in opposite ways: tiles hold about twice the
// render's records per pixel (records at a tile's edge serve pixels outside it), growing faster
// (samples^0.37 against 0.19 on Sponza), and the pilots' passes trace 6-11 rays a sample, most for
// the records they make, against the render's 2. The growth is capped at 0.5 (records fill in).
double recordPathsShare(const AutoPilot& pilot, double renderSamples, double pixels) {
    if (!(renderSamples > 0 && std::isfinite(renderSamples))) return 1.0;  // no rate measured: no shrink
    const double growth = std::pow(std::max(1.0, renderSamples / std::max(pilot.cacheSamples, 1e-3)),
                                   std::clamp(pilot.recordGrowth, 0.0, 0.5));
    const double records = std::max(1.0, pilot.recordsPerPixel * pixels * growth);
    const double paths =
        pilot.passRaysPerSample * renderSamples * pixels / std::max(pilot.recordRaysPerPath, 1e-3) / records;
    return std::min(1.0, pilot.recordPaths / std::max(paths, pilot.recordPaths));
}

// The samples per pixel a render of `pixels` takes in `seconds` after its preprocessing, at the
// pilot's rates (AutoPilot::steadySecondsPerSample and the start-up and refinement beside it):
// `scale` is the render's pixels over the pilot's, `fillScale` its fill's rays over the pilot's.
// Infinite where no rate was measured.
double samplesInTime(const AutoPilot& pilot, double seconds, double scale, double fillScale, double pixels) {
    if (!(pilot.steadySecondsPerSample > 0)) return std::numeric_limits<double>::infinity();
    auto startup = [&](double samples) {
        const double past = pilot.startupSamples > 0 ? std::max(1.0, samples / pilot.startupSamples) : 1.0;
        return scale * (pilot.startupSeconds + pilot.startupGrowthSeconds * std::log(past));
    };
    auto cost = [&](double samples) {
        double t = samples * pixels * pilot.steadySecondsPerSample + startup(samples);
        if (pilot.recordRaySeconds > 0) {  // past the fill's rays, a record ray for each pass ray
            const double passRays = samples * pixels * pilot.steadyRaysPerSample + startup(samples) / pilot.recordRaySeconds;
            t += pilot.recordRaySeconds * std::max(0.0, passRays - fillScale * pilot.fillRays);
        }
        return t;
    };
    seconds = std::max(seconds, 1e-3);
    double lo = 1e-6, hi = 1e9;  // cost grows with the samples: bisection on their logarithm
    if (cost(hi) <= seconds) return hi;
    if (cost(lo) >= seconds) return lo;
    for (int i = 0; i < 100; ++i) {
        const double mid = std::sqrt(lo * hi);
        (cost(mid) > seconds ? hi : lo) = mid;
    }
    return lo;
}
}  // namespace

std::string AutoChoice::summary() const {
    if (kept) return "auto: kept " + integrator + ", chosen by an earlier render (no pilots)";
    const std::string pixels = pilotTile > 0 ? std::to_string(pilotTiles) + " tiles of " + std::to_string(pilotTile) +
                                                   "x" + std::to_string(pilotTile) + " pixels"
                                             : "the whole image";
    std::string text = "auto: chose " + integrator + " for " + std::to_string(int(std::lround(budgetSeconds))) +
                       " s after " + std::to_string(pilotSeconds).substr(0, 4) + " s of pilots on " + pixels +
                       "; predicted RMSE (sRGB codes; its square = bias + cache noise + sample noise; a kept bias's "
                       "standard error after it; the samples per pixel it renders):";
    for (const AutoPrediction& p : predictions) {
        char buffer[256];
        char error[32] = "";  // a kept bias's standard error (AutoPrediction::biasError)
        if (p.biasError > 0) std::snprintf(error, sizeof error, " +- %.2f", p.biasError);
        char samples[32] = "";  // the samples per pixel the prediction is for
        if (p.predictedSamples > 0) std::snprintf(samples, sizeof samples, "; %.0f spp", p.predictedSamples);
        if (p.complete)
            std::snprintf(buffer, sizeof buffer, " %s %.2f (%.2f%s + %.2f + %.2f%s)%s", p.integrator.c_str(),
                          p.predictedRmse, p.predictedBias, error, p.predictedCacheNoise, p.predictedSampleNoise,
                          samples, &p == &predictions.back() ? "" : ",");
        else  // its pilot rendered fewer than two batches in its share
            std::snprintf(buffer, sizeof buffer,
                          " %s (no pilot in time: %d of %d batches in %.2f s, %.2f s of it preprocessing)%s",
                          p.integrator.c_str(), p.batches, kAutoPilotBatches, p.pilotSeconds, p.preprocessSeconds,
                          &p == &predictions.back() ? "" : ",");
        text += buffer;
    }
    return text;
}


namespace {

// Each batch's deviation, per value, in codes at 1/q batches' samples: e_k = f(c_k + q d_k) - f(c_k)
// (auto_select.h), so that noise(q) over a group of values is the mean over k of their mean e_k,
// squared, over q: one value's as before, and a block's with the correlation its values' batches
// carry (a record shared by neighbours moves them together).
struct CodeDeviations {
    size_t batches = 0, n = 0;
    std::vector<double> e;        // batches x n, batch-major
    std::vector<double> ceiling;  // per value: max(f(M), 255 - f(M))^2, the largest error a value can have
};

CodeDeviations codeDeviations(const AutoPilot& pilot, double q) {
    CodeDeviations out;
    const auto& batches = pilot.batches;
    const size_t K = batches.size();
    if (K < 2 || !(q > 0)) return out;
    const size_t n = batches[0].size();
    // A batch's deviation is from the other batches of its cache (two caches differ by more).
    const size_t split = pilot.firstCacheBatches > 0 ? size_t(pilot.firstCacheBatches) : K;
    if (split < 2 || (split < K && K - split < 2)) return out;
    out.batches = K, out.n = n;
    out.e.assign(K * n, 0.0);
    out.ceiling.assign(n, 0.0);
    // Batches are time slices, so their samples differ (a cache's first samples, which make its
    // records, cost more: on Sibenik at 37x28 an irradiance cache's four made 5, 13, 16 and 28).
    // A batch's deviation is from its cache's other batches' sample-weighted mean M', and with
    // per-sample variance s^2, Var(B_k - M') = s^2 (1 / n_k + 1 / N'), N' the others' samples: it
    // is scaled to a batch of the mean samples n, whose variance is s^2 / n. (From the others'
    // unweighted mean, a small batch among them made every other batch's deviation too large:
    // 1.15 times the noise for those four, 1.4 for 7, 29, 59 and 75 samples.)
    std::vector<double> samples(K, 1.0);
    if (pilot.batchSamples.size() == K)
        for (size_t k = 0; k < K; ++k) samples[k] = std::max(pilot.batchSamples[k], 1e-9);
    double meanSamples = 0, firstSamples = 0;
    for (size_t k = 0; k < K; ++k) {
        meanSamples += samples[k] / double(K);
        if (k < split) firstSamples += samples[k];
    }
    std::vector<double> total(n, 0.0), weighted(n, 0.0), firstWeighted(n, 0.0);
    for (size_t k = 0; k < K; ++k)
        for (size_t i = 0; i < n; ++i) {
            total[i] += batches[k][i];
            weighted[i] += samples[k] * batches[k][i];
            if (k < split) firstWeighted[i] += samples[k] * batches[k][i];
        }
    for (int y = 0; y < pilot.height; ++y)
        for (int x = 0; x < pilot.width; ++x)
            for (int channel = 0; channel < 3; ++channel) {
                const size_t i = (size_t(y) * size_t(pilot.width) + size_t(x)) * 3 + size_t(channel);
                // The window, within the pixel's tile (its neighbours in the image), clipped there.
                const int x0 = pilot.tile > 0 ? x / pilot.tile * pilot.tile : 0,
                          x1 = pilot.tile > 0 ? x0 + pilot.tile - 1 : pilot.width - 1;
                const int y0 = pilot.tile > 0 ? y / pilot.tile * pilot.tile : 0,
                          y1 = pilot.tile > 0 ? y0 + pilot.tile - 1 : pilot.height - 1;
                // The window's values in every batch, and how many there are.
                double window = 0;
                int count = 0;
                for (int v = std::max(y0, y - 1); v <= std::min(y1, y + 1); ++v)
                    for (int u = std::max(x0, x - 1); u <= std::min(x1, x + 1); ++u, ++count)
                        window += total[(size_t(v) * size_t(pilot.width) + size_t(u)) * 3 + size_t(channel)];
                for (size_t k = 0; k < K; ++k) {
                    const bool first = k < split;
                    const double groupWeighted = first ? firstWeighted[i] : weighted[i] - firstWeighted[i];
                    const double groupSamples = first ? firstSamples : meanSamples * double(K) - firstSamples;
                    const double othersSamples = groupSamples - samples[k];
                    double value = batches[k][i];
                    double center = (window - value) / double(size_t(count) * K - 1);
                    // A window that clips (a light beside the pixel) would hide the pixel's own
                    // noise (f' = 0 there): its own other batches' mean is taken instead.
                    const double own = (total[i] - value) / double(K - 1);
                    if (center >= 1 && own < 1) center = own;
                    const double others = (groupWeighted - samples[k] * value) / othersSamples;
                    double deviation = (value - others) /
                                       std::sqrt(meanSamples * (1.0 / samples[k] + 1.0 / othersSamples));
                    out.e[k * n + i] = srgbCode(center + q * deviation) - srgbCode(center);
                }
                double meanCode = srgbCode(total[i] / double(K)), farthest = std::max(meanCode, 255.0 - meanCode);
                out.ceiling[i] = farthest * farthest;
            }
    return out;
}

}  // namespace

BiasBlocks biasBlocks(const AutoPilot& layout, const std::vector<uint8_t>* kept, int side) {
    BiasBlocks blocks;
    const size_t n = size_t(layout.width) * size_t(layout.height) * 3;
    blocks.of.assign(n, -1);
    side = std::max(1, side);
    // Blocks start at each tile's corner (the pilot's tiles are apart in the image) and are clipped
    // at its far edges; a block holds one colour channel.
    const int tile = layout.tile > 0 ? layout.tile : std::max(layout.width, layout.height);
    const int across = (tile + side - 1) / side;
    const int tilesAcross = (layout.width + tile - 1) / tile;
    for (int y = 0; y < layout.height; ++y)
        for (int x = 0; x < layout.width; ++x)
            for (int channel = 0; channel < 3; ++channel) {
                const size_t i = (size_t(y) * size_t(layout.width) + size_t(x)) * 3 + size_t(channel);
                if (kept && !(*kept)[i]) continue;
                const int tileIndex = (y / tile) * tilesAcross + x / tile;
                const int inTile = ((y % tile) / side) * across + (x % tile) / side;
                blocks.of[i] = (tileIndex * across * across + inTile) * 3 + channel;
                blocks.count = std::max(blocks.count, blocks.of[i] + 1);
            }
    return blocks;
}

double predictedNoise(const AutoPilot& pilot, const BiasBlocks& blocks, double q) {
    const CodeDeviations d = codeDeviations(pilot, q);
    if (d.batches == 0 || blocks.count == 0 || blocks.of.size() != d.n) return 0;
    std::vector<double> size(size_t(blocks.count), 0.0), ceiling(size_t(blocks.count), 0.0),
        sum(size_t(blocks.count) * d.batches, 0.0);
    for (size_t i = 0; i < d.n; ++i) {
        const int b = blocks.of[i];
        if (b < 0) continue;
        size[size_t(b)] += 1;
        ceiling[size_t(b)] += d.ceiling[i];
        for (size_t k = 0; k < d.batches; ++k) sum[size_t(b) * d.batches + k] += d.e[k * d.n + i];
    }
    double total = 0, values = 0;
    for (size_t b = 0; b < size.size(); ++b) {
        if (size[b] == 0) continue;
        double block = 0;
        for (size_t k = 0; k < d.batches; ++k) {
            const double mean = sum[b * d.batches + k] / size[b];
            block += mean * mean;
        }
        // A block's mean error is bounded as its values' are (their squared distances to code 0 or 255).
        total += size[b] * std::min(block / (double(d.batches) * q), ceiling[b] / size[b]);
        values += size[b];
    }
    return values > 0 ? total / values : 0;
}

double predictedNoise(const AutoPilot& pilot, double q, const std::vector<uint8_t>* kept) {
    return predictedNoise(pilot, biasBlocks(pilot, kept, 1), q);
}

namespace {

// A pilot's bias estimate against R (auto_select.h: e, c2, b2 before its clamp at 0), with the
// cache noise parts it subtracts.
struct BiasEstimate {
    double bias = 0;               // b2, unclamped
    double cacheNoise = 0;         // c2: the first cache's own noise
    double meanCacheNoise = 0;     // what of the caches' noise the pilot's mean holds, over the kept values
    double sharedSampleNoise = 0;  // the two caches' common samples' part of the mean's noise
};

// Over `blocks` (the kept values in blocks of kBiasBlock: the bias is their mean's), with R's
// noise over them `referenceVariance`.
BiasEstimate estimateBias(const AutoPilot& pilot, const std::vector<double>& referenceCodes, double referenceVariance,
                          const BiasBlocks& blocks) {
    BiasEstimate estimate;
    const std::vector<double> codes =
        srgbCodes(meanImage(pilot.batches, sampleWeights(pilot, 0, pilot.batches.size())));
    const double error = meanSquaredDifference(codes, referenceCodes, blocks) - referenceVariance;
    const double keptNoise = predictedNoise(pilot, blocks, 1.0 / double(pilot.batches.size()));
    const size_t split = size_t(pilot.firstCacheBatches);
    const std::pair<double, double> photonsShort = photonsShortOf(pilot);
    if (split > 0) {
        // Two caches of the same camera samples, batch for batch (common random numbers):
        // their paired batches' mean difference, less the noise of that difference (its
        // spread over the pairs), is both caches' own noise. Unpaired, the samples' noise
        // of both means had to be subtracted: on Sponza at 160x120 about 600 codes squared,
        // estimated to within 10-20%, against some 50 of the caches' own.
        const size_t pairs = std::min(split, pilot.batches.size() - split);
        const AutoPilot firstCache = cachePilot(pilot, 0, pairs),
                        secondCache = cachePilot(pilot, split, split + pairs);
        const AutoPilot differences = pairedDifferences(firstCache, secondCache);
        const std::vector<double> firstCodes = srgbCodes(meanImage(firstCache.batches, firstCache.batchSamples));
        const std::vector<double> secondCodes = srgbCodes(meanImage(secondCache.batches, secondCache.batchSamples));
        // The difference's noise, over `values`: from the pairs' spread, which also holds how
        // the caches' difference drifts from batch to batch (the records their batches add:
        // on the Cornell box the photon cache's pairs spread by 25.6 codes squared, its
        // batches by 1.2 each), or as the two means' noise, which counts their common samples'
        // as if apart; each is at least the noise, so the smaller.
        auto differenceNoise = [&](const BiasBlocks& values) {
            return std::min(predictedNoise(differences, values, 1.0 / double(pairs)),
                            predictedNoise(firstCache, values, 1.0 / double(pairs)) +
                                predictedNoise(secondCache, values, 1.0 / double(pairs)));
        };
        auto excess = [&](const BiasBlocks& values, double noise) {
            return std::max(0.0, meanSquaredDifference(firstCodes, secondCodes, values) - noise);
        };
        const double keptDifferenceNoise = differenceNoise(blocks);
        // A photon map's noise goes as 1 / its photons: each cache's as x_j, its photons'
        // shortfall from the render's (1 / photonShare), and the first cache's is the
        // difference's x_1 / (x_1 + x_2) (a half with alike caches).
        const double firstShare = photonsShort.first / (photonsShort.first + photonsShort.second);
        // The render's cache noise is per value, over all of them.
        const BiasBlocks everyValue = biasBlocks(pilot, nullptr, 1);
        estimate.cacheNoise = excess(everyValue, differenceNoise(everyValue)) * firstShare;
        // The mean of all batches, weighed by their samples, holds w_1^2 c_1 + w_2^2 c_2 of it.
        double firstSamples = 0, allSamples = 0;
        for (size_t b = 0; b < pilot.batches.size(); ++b) {
            const double samples = pilot.batchSamples.size() == pilot.batches.size() ? pilot.batchSamples[b] : 1;
            allSamples += samples;
            if (b < split) firstSamples += samples;
        }
        const double w1 = firstSamples / allSamples, w2 = 1 - w1;
        // Over the bias's values:
        estimate.meanCacheNoise = excess(blocks, keptDifferenceNoise) * firstShare *
                                  (w1 * w1 + w2 * w2 * photonsShort.second / photonsShort.first);
        // The caches share their samples, so the mean's noise has, beside each cache's own
        // (keptNoise), 2 w_1 w_2 Cov(M_1, M_2), and Var(M_1 - M_2) = V_1 + V_2 - 2 Cov.
        const double v1 = predictedNoise(cachePilot(pilot, 0, split), blocks, 1.0 / double(split)),
                     v2 = predictedNoise(cachePilot(pilot, split, pilot.batches.size()), blocks,
                                         1.0 / double(pilot.batches.size() - split));
        estimate.sharedSampleNoise = w1 * w2 * std::max(0.0, v1 + v2 - keptDifferenceNoise);
    }
    estimate.bias = error - keptNoise - estimate.sharedSampleNoise - estimate.meanCacheNoise;
    return estimate;
}

// The jackknife's standard error of b2: b2 again without each of the pilot's batches in turn (with
// two caches, without each pair of paired batches), R kept. 0 where fewer than three batches (pairs)
// leave nothing to compare.
double biasStandardError(const AutoPilot& pilot, const std::vector<double>& referenceCodes, double referenceVariance,
                         const BiasBlocks& blocks) {
    const size_t K = pilot.batches.size(), split = size_t(pilot.firstCacheBatches);
    const size_t units = split > 0 ? std::min(split, K - split) : K;
    if (units < 3) return 0;
    std::vector<double> biases;
    for (size_t u = 0; u < units; ++u) {
        AutoPilot part = pilot;
        auto drop = [&](size_t index) {
            part.batches.erase(part.batches.begin() + long(index));
            if (part.batchSamples.size() == K) part.batchSamples.erase(part.batchSamples.begin() + long(index));
        };
        if (split > 0) {
            drop(split + u);
            drop(u);
            part.firstCacheBatches = int(split - 1);
        } else {
            drop(u);
        }
        biases.push_back(estimateBias(part, referenceCodes, referenceVariance, blocks).bias);
    }
    double mean = 0, spread = 0;
    for (double b : biases) mean += b / double(units);
    for (double b : biases) spread += (b - mean) * (b - mean);
    return std::sqrt(spread * double(units - 1) / double(units));
}

}  // namespace

AutoChoice predictFromPilots(const std::vector<AutoPilot>& pilots, double pilotPixels, double pixels,
                             double budgetSeconds, int biasBlock) {
    AutoChoice choice;
    choice.budgetSeconds = budgetSeconds;
    // Each technique's mean image (in codes) and its noise; the consistent techniques'
    // inverse-variance mean R.
    size_t n = 0;
    for (const AutoPilot& p : pilots)
        if (p.complete) n = p.batches[0].size();
    std::vector<std::vector<double>> means(pilots.size());
    std::vector<double> meanNoise(pilots.size());  // noise(1 / K): of the mean of its K batches
    // A floor on the variance keeps a noiseless pilot from taking all the weight.
    constexpr double kNoiseFloor = 1e-3;
    // The path tracer misses light when its pilot is darker than the progressive photon map's by
    // more than this many standard errors of the difference and this share of the image's mean.
    constexpr double kMissSigmas = 4, kMissShare = 0.02;
    for (size_t k = 0; k < pilots.size(); ++k) {
        if (!pilots[k].complete) continue;
        means[k] = meanImage(pilots[k].batches, sampleWeights(pilots[k], 0, pilots[k].batches.size()));
        meanNoise[k] = predictedNoise(pilots[k], 1.0 / double(pilots[k].batches.size()));
    }
    // R, the consistent pilots' inverse-variance mean, counts the progressive photon map's blur as
    // its variance: its pilot's first radii are wide, and wider in the world with the pilot's
    // photons (4 to 5 codes RMSE on the Cornell box, as much as the caches' whole error), and the
    // blur is its mean's difference from the path tracer's, less both noises. Unless the path
    // tracer misses light (a sun through glass), which shows as a darker typical batch: a blur
    // keeps the image's mean, a miss does not. R is mixed in codes, where its error is measured: mixed as
    // linear values, the photon map's blur of a bright light (values far above 1) into dark pixels
    // clips their codes whatever its weight, so R's error exceeded what the weights say (Cornell
    // box at 60 s, three runs: 6.0 to 7.2 codes squared where they said 4.8 to 5.0; mixed in codes
    // 5.3 to 6.1, and the caches' bias estimates moved from 1.2 to 0.5 above what their pilots'
    // own errors held, on average; bench/pilot_accuracy.py).
    const AutoPilot* path = nullptr;
    const AutoPilot* progressive = nullptr;
    size_t pathIndex = 0, progressiveIndex = 0;
    for (size_t k = 0; k < pilots.size(); ++k)
        if (pilots[k].complete && pilots[k].integrator == "path") path = &pilots[pathIndex = k];
        else if (pilots[k].complete && pilots[k].integrator == "progressivePhotonMap")
            progressive = &pilots[progressiveIndex = k];
    double progressiveBlur = 0;
    bool pathMisses = false;
    if (path && progressive) {
        double pathMean, pathVariance, progressiveMean, progressiveVariance;
        typicalBrightness(*path, pathMean, pathVariance);
        typicalBrightness(*progressive, progressiveMean, progressiveVariance);
        pathMisses = progressiveMean - pathMean >
                     std::max(kMissSigmas * std::sqrt(pathVariance + progressiveVariance), kMissShare * progressiveMean);
        if (!pathMisses)
            progressiveBlur = std::max(0.0, meanSquaredDifference(srgbCodes(means[progressiveIndex]),
                                                                  srgbCodes(means[pathIndex])) -
                                                meanNoise[progressiveIndex] - meanNoise[pathIndex]);
    }
    std::vector<double> referenceCodes(n, 0.0);
    double weightSum = 0;
    // The bias estimates' values, each pilot's mean's noise over them, and R's there.
    const std::vector<uint8_t> kept = valuesForBias(path, n);
    BiasBlocks blocks;
    std::vector<double> keptNoise(pilots.size(), 0.0);
    for (size_t k = 0; k < pilots.size(); ++k)
        if (pilots[k].complete) {
            if (blocks.of.empty()) blocks = biasBlocks(pilots[k], &kept, biasBlock);
            keptNoise[k] = predictedNoise(pilots[k], blocks, 1.0 / double(pilots[k].batches.size()));
        }
    // The blur R holds in the blocks' means: a blur that alternates from pixel to pixel (an
    // edge spread both ways) falls there as noise does.
    double progressiveBlockBlur = 0;
    if (progressiveBlur > 0)
        progressiveBlockBlur = std::max(0.0, meanSquaredDifference(srgbCodes(means[progressiveIndex]),
                                                                   srgbCodes(means[pathIndex]), blocks) -
                                                 keptNoise[progressiveIndex] - keptNoise[pathIndex]);
    double keptVarianceSum = 0;  // sum of w^2 (noise + blur) over the kept values' blocks
    for (size_t k = 0; k < pilots.size(); ++k) {
        if (!pilots[k].complete || !isConsistentTechnique(pilots[k].integrator)) continue;
        const bool blurs = &pilots[k] == progressive;
        double w = 1.0 / (meanNoise[k] + (blurs ? progressiveBlur : 0) + kNoiseFloor);
        keptVarianceSum += w * w * (keptNoise[k] + (blurs ? progressiveBlockBlur : 0) + kNoiseFloor);
        weightSum += w;
        const std::vector<double> codes = srgbCodes(means[k]);
        for (size_t i = 0; i < n; ++i) referenceCodes[i] += w * codes[i];
    }
    choice.integrator = "path";
    // Without a consistent technique's pilot there is nothing to measure bias against: every
    // prediction is left out, and the choice is the unbiased technique.
    const bool compared = weightSum > 0;
    for (double& r : referenceCodes) r /= compared ? weightSum : 1;
    // R's mean squared error, its noise and the blur it holds (1 / the weights' sum over all
    // values), over the kept values.
    const double referenceVariance = compared ? keptVarianceSum / (weightSum * weightSum) : 0;

    double pathMse = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < pilots.size(); ++k) {
        AutoPrediction p;
        p.integrator = pilots[k].integrator;
        p.consistent = isConsistentTechnique(p.integrator);
        p.complete = pilots[k].complete && compared;
        p.batches = int(pilots[k].batches.size());
        p.pilotSeconds = pilots[k].seconds;
        p.preprocessSeconds = pilots[k].preprocessSeconds;
        if (p.complete) {
            const double batches = double(pilots[k].batches.size());
            p.noise = predictedNoise(pilots[k], 1.0);
            const AutoPilot& pilot = pilots[k];
            const size_t split = size_t(pilot.firstCacheBatches);
            const bool photonLaw = hasPhotonLaw(pilot);
            const std::pair<double, double> photonsShort = photonsShortOf(pilot);
            const BiasEstimate estimate = estimateBias(pilot, referenceCodes, referenceVariance, blocks);
            p.cacheNoise = estimate.cacheNoise;
            p.bias = std::max(0.0, estimate.bias);
            if (!p.consistent) p.biasError = biasStandardError(pilot, referenceCodes, referenceVariance, blocks);
            // R holds part of the photon map's own blur: against the path tracer it shows whole.
            // Its pilot's radii are wider in the world by the square root of the pixel counts'
            // ratio (scalePhotonCounts), and its squared blur grows with the radius: on the
            // Cornell box at 37x28
            // (40,000 photons a pass, 64 samples) 10.5, 4.6 and 0.64 codes squared at 4, 2 and
            // 0.92 pixels, a power of 1.9 over the whole range. Taken as r^2: the render's blur
            // is the pilot's times the ratio of the pixel counts. A bias that is no blur (a map
            // 3.7% dark, its portal photons missing light: docs/auto.md, "Correction") is read as one
            // too, and predicted to shrink: 0.24-0.27 codes squared for about 1.3 reached.
            if (&pilot == progressive && !pathMisses) p.bias = progressiveBlur * std::min(1.0, pilotPixels / pixels);
            // The final render's time per pixel against one batch's: its preprocessing, as the
            // pilot's grown with the pixel count, takes at most its share of the budget.
            double finalPreprocess = std::min(kPreprocessShare * budgetSeconds,
                                              p.preprocessSeconds * pixels / pilotPixels);
            // One batch's samples over the render's, those at the pilot's rates.
            const double fillScale = p.preprocessSeconds > 0 ? finalPreprocess / p.preprocessSeconds : pixels / pilotPixels;
            const double meanSamples = meanBatchSamples(pilot);
            double ratio = std::min(1.0, meanSamples / samplesInTime(pilot, budgetSeconds - finalPreprocess,
                                                                     pixels / pilotPixels, fillScale, pixels));
            double biasShare = p.consistent ? std::min(1.0, batches * ratio) : 1.0, noiseShare = ratio;
            // A cache's own noise falls as its records gain paths with the camera's samples
            // (refineRecords), and a photon map's as its photons grow to the render's.
            double cacheShare = pilot.photonShare;
            if (pilot.records) {
                const double cacheBatches = split > 0 ? double(split) : batches;
                double recordShare = 1.0;
                if (pilot.refinesRecords)
                    recordShare = pilot.recordPaths > 0 ? recordPathsShare(pilot, meanSamples / ratio, pixels)
                                                        : std::min(1.0, cacheBatches * ratio);
                cacheShare = std::max(cacheShare, recordShare);
            }
            if (pilot.radiusAlpha > 0) {
                // Its radii shrink: its bias goes as the mean s_i, and its noise falls more
                // slowly than 1 / samples (as samples^-alpha), each pass noisier than the last.
                // Each batch took the indices [0, its samples).
                const double finalSamples = std::min(1e9, meanSamples / ratio);
                const double pilotSamples = std::max(1.0, meanSamples);
                const double a = pilot.radiusAlpha;
                const double blur = meanRadiusPower(a, 0, finalSamples, 1) / meanRadiusPower(a, 0, pilotSamples, 1);
                biasShare = std::min(1.0, blur * blur);
                noiseShare = std::min(1.0, ratio * meanRadiusPower(a, 0, finalSamples, -1) /
                                               meanRadiusPower(a, 0, pilotSamples, -1));
            }
            p.predictedBias = p.bias * biasShare;
            p.predictedCacheNoise = p.cacheNoise * cacheShare;
            if (pilot.radiusAlpha > 0 && pilot.rayTracedBatches.size() >= 2 &&
                pilot.rayTracedBatches[0].size() == pilot.batches[0].size()) {
                // Of each sample's noise only the photons' grows as the radii shrink.
                const AutoPilot rayTraced = rayTracedPart(pilot);
                const double scale = meanBatchSamples(rayTraced) / std::max(meanSamples, 1e-9);
                p.predictedSampleNoise =
                    predictedNoise(rayTraced, ratio * scale) +
                    std::max(0.0, predictedNoise(pilot, noiseShare) - predictedNoise(rayTraced, noiseShare * scale));
            } else if (!photonLaw) {
                p.predictedSampleNoise = predictedNoise(pilot, noiseShare);
            } else {
                // Each camera sample reads the photon map, so its noise falls with the photons too:
                // a + b x, x the photons' shortfall, from the two caches' noise at the render's
                // samples (on the Cornell box, final gathering's noise x samples was 157 at the
                // pilot's 27,000 photons and 73 at the render's 500,000: bench/pilot_accuracy.py).
                const AutoPilot first = cachePilot(pilot, 0, split), second = cachePilot(pilot, split, pilot.batches.size());
                const double v1 = predictedNoise(first, noiseShare * meanBatchSamples(first) / meanSamples),
                             v2 = predictedNoise(second, noiseShare * meanBatchSamples(second) / meanSamples);
                p.predictedSampleNoise = noiseAtTheRendersPhotons(v1, photonsShort.first, v2, photonsShort.second);
            }
            if (ratio > 0) p.predictedSamples = meanSamples / ratio;
            double mse = p.predictedBias + p.predictedCacheNoise + p.predictedSampleNoise;
            p.predictedRmse = std::sqrt(mse);
            if (p.integrator == "path") pathMse = mse;
        }
        choice.predictions.push_back(p);
    }
    double best = pathMse * kAutoMargin;
    for (const AutoPrediction& p : choice.predictions) {
        double mse = p.predictedRmse * p.predictedRmse;
        if (p.complete && p.integrator != "path" && mse < best) {
            best = mse;
            choice.integrator = p.integrator;
        }
    }
    return choice;
}

}  // namespace gi
