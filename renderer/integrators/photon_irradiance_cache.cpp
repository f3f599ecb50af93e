#include "photon_irradiance_cache.h"

#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>

#include "progressive_fill.h"
#include "specular_chain.h"

namespace gi {

namespace {
// Pixel streams of the fill pass use a sample index the render never reaches.
constexpr uint32_t kFillSampleIndex = 0xfffffff2u;
// A photon record only where the photons cover this much of their disc (PhotonEstimate::coverage):
// a disc over an edge or a thin column holds fewer photons than its area says, and the record
// would read dark (at 0.7, at least about 85% of the disc is surface, simulated). Over a full
// disc the measure falls below 0.7 in about 8% of estimates of 50 photons and 1% of 100: those
// records are path-traced, which costs time, not accuracy. Sponza under sun and sky (128x96, 4
// spp, against the path tracer): 0.966, 0.921, 0.900 with 0.5, 2.5, 10 million photons before
// (more photons, more photon records on its columns and edges), 0.994, 0.990, 0.991 with it
// (0.989 at 0.6, 0.990-0.995 at 0.75).
constexpr float kMinCoverage = 0.7f;
// Global photon batches are added between passes while their rays are fewer than the passes' rays
// times this, times the share of photon records in the cache (none where every record is path
// traced: Sibenik under its sky). Measured at 160x120, 5 s, FLIP against 90 s references, shares
// 0 / 0.5 / 1 / 2: sky-lit room 0.0506 / 0.0429 / 0.0408 / 0.0404, sunlit room (sun through
// glass) 0.0915 / 0.0917 / 0.0915 / 0.0834, Sponza 0.0925 / 0.0918 / 0.0907 / 0.0914.
constexpr double kPhotonShare = 2;
// A photon record's sigma: the standard deviation of Y(E) for n photons, Y / sqrt(n).
float photonSigma(const PhotonEstimate& e) { return luminance(e.value) / std::sqrt(float(e.photons)); }
}  // namespace

PhotonMapIrradianceCacheIntegrator::PhotonMapIrradianceCacheIntegrator(const PhotonIrradianceCacheSettings& settings)
    : DirectIntegrator(settings.record.rayDepth, settings.lightSamples), settings_(settings), cache_(settings.record.accuracy) {
    tracesGlossy_ = true;
    settings_.photons.globalKeepsDirectAndCaustic = false;
    // The sky through glass is the records' (path-traced ones find it by BSDF sampling, photon
    // records from the global map), not a caustic map's sparse photons over wide discs.
    settings_.photons.causticMapLeavesOutDomes = true;
    settings_.photons.globalKeepsDomeCaustics = true;
    settings_.photons.rayDepth = settings.record.rayDepth;
}

PhotonMapIrradianceCacheIntegrator::Site PhotonMapIrradianceCacheIntegrator::siteOf(const ShadingPoint& sp) const {
    return Site{RecordSite{sp.si.p, sp.si.ng, recordNormal(sp), sp.wo, footprint_.at(sp.si.p)},
                photonSurface(sp.si.shapeId, sp.si.instanceId)};
}

bool PhotonMapIrradianceCacheIntegrator::photonIrradiance(const Scene& scene, const RecordSite& site, uint32_t surface,
                                                          PhotonEstimate* estimate) const {
    const int k = recordPhotons_;
    *estimate = maps_.global.irradiance(PhotonLookup{site.p, site.n, surface, &scene, site.ng}, k, maps_.gatherRadius);
    return estimate->photons >= (k + 1) / 2 && estimate->coverage >= kMinCoverage;
}

IrradianceRecord PhotonMapIrradianceCacheIntegrator::computeRecord(const Scene& scene, const Site& where,
                                                                   RayStats& stats, Counters& counters) const {
    const RecordSite& site = where.record;
    PhotonEstimate estimate;
    if (photonIrradiance(scene, site, where.surface, &estimate)) {
        const RecordSettings& r = settings_.record;
        IrradianceRecord record;
        record.p = site.p;
        record.n = site.n;
        record.E = estimate.value;
        record.footprint = site.footprint;
        record.ng = site.ng;
        record.wo = site.wo;
        record.radius = std::clamp(0.5f * estimate.radius / r.accuracy, r.minSpacing * site.footprint,
                                   std::max(r.minSpacing, r.maxSpacing) * site.footprint);
        record.sigma = photonSigma(estimate);
        counters.photonRecords.fetch_add(1, std::memory_order_relaxed);
        return record;
    }
    counters.pathTracedRecords.fetch_add(1, std::memory_order_relaxed);
    const uint64_t raysBefore = stats.rays;
    IrradianceRecord record = recordSampler_->sample(scene, site, seed_, IrradianceRecordSampler::streamKey(site), stats);
    counters.pathTracedRays.fetch_add(stats.rays - raysBefore, std::memory_order_relaxed);
    return record;
}

bool PhotonMapIrradianceCacheIntegrator::interpolate(const Scene& scene, const Site& site, bool relaxed,
                                                     Color* E) const {
    std::vector<IrradianceCache::Contribution> contributions;
    cache_.gather(site.record.p, site.record.n, contributions, relaxed);
    Color weighted(0.0f);
    float weightSum = 0;
    for (const IrradianceCache::Contribution& c : contributions) {
        const IrradianceRecord& record = cache_.record(c.record);
        if (recordSurfaces_[c.record] != site.surface &&
            !clearBetween(scene, site.record.p, site.record.n, record.p, record.n, 0.05f * length(record.p - site.record.p)))
            continue;
        weighted += c.E * c.weight;
        weightSum += c.weight;
    }
    if (!(weightSum > 0)) return false;
    *E = weighted / weightSum;
    return true;
}

void PhotonMapIrradianceCacheIntegrator::preprocess(const PreprocessContext& context) {
    seed_ = context.seed;
    footprint_ = PixelFootprint::of(context.camera);
    buildPhotonMaps(context, settings_.photons, maps_);
    recordPhotons_ = settings_.photons.gatherPhotons;
    if (maps_.global.empty() && settings_.photons.photons > 0)
        context.scene.warn("photonMapIrradianceCache: the global photon map is empty, so every irradiance record "
                           "is path traced");
    CausticPhotons caustics;
    // The caustic map, read through the whole BSDF at a glossy point, has what its glossy rays
    // would find through specular surfaces, but the domes.
    glossyBranchEmitters_ = maps_.caustic.empty() ? BranchEmitters::All : BranchEmitters::DomesOnly;
    if (!maps_.caustic.empty())
        caustics = CausticPhotons{&maps_.caustic, settings_.photons.gatherPhotons, maps_.causticRadius,
                                  kCausticConeFilter,
                                  kRecordCausticShare};
    recordSampler_ = std::make_unique<PathTracedRecordSampler>(settings_.record, caustics);
    refinement_ = std::make_unique<RecordRefinement>(HemisphereLayout::forPaths(settings_.record.paths).cells());
    auto start = std::chrono::steady_clock::now();
    cache_.reset(context.scene.bounds().center, context.scene.bounds().radius);
    recordSurfaces_.clear();
    fillFromPixelCentres(context);
    fillSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void PhotonMapIrradianceCacheIntegrator::fillFromPixelCentres(const PreprocessContext& context) {
    PixelPhases phases(context.width, context.height, settings_.record.maxSpacing);
    int phase = 0;
    for (const std::vector<uint32_t>& pixels : phases.pixelsByPhase()) {
        if (context.cancel && context.cancel->load()) return;
        if (context.pastDeadline()) {  // the render computes the records still missing
            context.scaledDown("irradiance cache fill stopped after phase " + std::to_string(phase) + " of " +
                               std::to_string(phases.count()));
            return;
        }
        ++phase;
        // The non-specular points the ray tracer will shade, per fixed-size chunk of pixels,
        // concatenated in chunk order: pixel order.
        constexpr size_t kChunk = 64;
        std::vector<std::vector<Site>> chunks((pixels.size() + kChunk - 1) / kChunk);
        tbb::parallel_for(size_t(0), chunks.size(), [&](size_t chunk) {
            Sampler sampler(seed_);
            RayStats stats;
            for (size_t i = chunk * kChunk; i < std::min(pixels.size(), (chunk + 1) * kChunk); ++i) {
                int x = int(pixels[i] % uint32_t(context.width)), y = int(pixels[i] / uint32_t(context.width));
                sampler.start(x, y, kFillSampleIndex);
                Ray ray = context.camera.generateRay(x + 0.5f, y + 0.5f, Vec2(0.5f, 0.5f));
                forEachDiffuseHit(context.scene, ray, sampler, stats, rayDepth_, [&](const ShadingPoint& sp) {
                    if (!isBlack(sp.bsdf.diffuseReflectance())) chunks[chunk].push_back(siteOf(sp));
                });
            }
        });
        std::vector<Site> sites;
        for (auto& chunk : chunks) sites.insert(sites.end(), chunk.begin(), chunk.end());
        // Coverage against the cache as the phase found it, records in parallel, inserted in
        // site order: the cache's content is a function of the seed.
        std::vector<uint8_t> missing(sites.size(), 0);
        tbb::parallel_for(size_t(0), sites.size(), [&](size_t i) {
            Color E;
            missing[i] = !interpolate(context.scene, sites[i], false, &E);
        });
        std::vector<size_t> wanted;
        for (size_t i = 0; i < sites.size(); ++i)
            if (missing[i]) wanted.push_back(i);
        std::vector<IrradianceRecord> records(wanted.size());
        tbb::parallel_for(size_t(0), wanted.size(), [&](size_t i) {
            RayStats stats;
            records[i] = computeRecord(context.scene, sites[wanted[i]], stats, preprocessRecords_);
        });
        for (size_t i = 0; i < records.size(); ++i) {
            cache_.insert(records[i]);
            recordSurfaces_.push_back(sites[wanted[i]].surface);
        }
    }
}

void PhotonMapIrradianceCacheIntegrator::beginPass(const PreprocessContext& context, int, int) {
    for (const RenderTimeRecords::Entry& e : renderTimeRecords_.take()) {
        Color E;
        Site site{recordSite(e.record), e.surface};
        if (interpolate(context.scene, site, false, &E)) continue;
        cache_.insert(e.record);
        recordSurfaces_.push_back(e.surface);
        ++adoptedRecords_;
    }
    if (!settings_.refineRecords) return;
    addPhotonBatches(context);
    if (!refinement_) return;
    refinement_->beforePass(context, preprocessRecords_.pathTracedRays.load(), cache_,
                            [&](const RecordSite& site, uint32_t key, uint32_t before, RayStats& stats) {
                                return recordSampler_->sample(context.scene, site, seed_, key, stats, before);
                            });
}

void PhotonMapIrradianceCacheIntegrator::addPhotonBatches(const PreprocessContext& context) {
    const PhotonSource* source = maps_.source.get();
    if (!source) return;
    size_t photonRecords = 0;
    for (uint32_t id = 0; id < cache_.size(); ++id) photonRecords += cache_.record(id).samples == 0;
    const double share = kPhotonShare * double(photonRecords) / double(std::max<size_t>(1, cache_.size()));
    const int before = maps_.batches;
    while (double(source->globalRays) * maps_.batches < share * double(context.passRays)) {
        if (context.deadline > 0) {  // a batch must leave the pass most of the time left
            const auto& s = maps_.statistics;
            double batchSeconds = s.at("photonTraceSeconds") + s.at("photonMapBuildSeconds") * maps_.batches;
            if (batchSeconds > 0.25 * context.secondsLeft()) break;
        }
        if (addPhotonBatch(context, maps_) == 0) break;
    }
    if (maps_.batches == before) return;
    // Photon records read the denser global map with more photons, k B^(2/3) for B batches (as a
    // progressive photon map's radius schedule, alpha = 2/3): both their noise and their disc
    // shrink as the photons grow.
    recordPhotons_ = int(std::lround(settings_.photons.gatherPhotons * std::pow(double(maps_.batches), 2.0 / 3.0)));
    tbb::parallel_for(uint32_t(0), uint32_t(cache_.size()), [&](uint32_t id) {
        const IrradianceRecord& record = cache_.record(id);
        if (record.samples > 0) return;
        PhotonEstimate estimate;
        if (photonIrradiance(context.scene, recordSite(record), recordSurfaces_[id], &estimate))
            cache_.reestimate(id, estimate.value, photonSigma(estimate));
    });
}

Color PhotonMapIrradianceCacheIntegrator::indirect(const Scene& scene, const ShadingPoint& sp, Sampler& sampler,
                                                   RayStats& stats) const {
    Color L(0.0f);
    if (!maps_.caustic.empty())
        L += maps_.caustic.radiance(sp, scene, settings_.photons.gatherPhotons, maps_.causticRadius, kCausticConeFilter)
                 .value;
    Color reflectance = sp.bsdf.diffuseReflectance();
    if (isBlack(reflectance)) return L;
    lookups_.fetch_add(1, std::memory_order_relaxed);
    Site site = siteOf(sp);
    Color E;
    if (!interpolate(scene, site, false, &E) && !interpolate(scene, site, true, &E)) {
        // Nothing near enough: a record for this sample alone (a photon estimate, or a
        // path-traced record from a stream keyed by its site), not stored.
        const auto start = std::chrono::steady_clock::now();
        IrradianceRecord record = computeRecord(scene, site, stats, renderRecords_);
        renderRecords_.nanoseconds.fetch_add(
            uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start).count()),
            std::memory_order_relaxed);
        E = record.E;
        renderTimeRecords_.add(record, site.surface);
    }
    return L + sp.bsdf.diffuseLobe(sp.woLocal) * E;
}

std::map<std::string, double> PhotonMapIrradianceCacheIntegrator::statistics() const {
    std::map<std::string, double> stats = maps_.statistics;
    stats["records"] = double(cache_.size());
    stats["recordSamplesClamped"] = recordSampler_ ? double(recordSampler_->outliersClamped()) : 0.0;
    stats["photonRecords"] = double(preprocessRecords_.photonRecords.load());
    stats["pathTracedRecords"] = double(preprocessRecords_.pathTracedRecords.load());
    stats["renderTimeRecords"] =
        double(renderRecords_.photonRecords.load() + renderRecords_.pathTracedRecords.load());
    stats["renderTimePathTracedRecords"] = double(renderRecords_.pathTracedRecords.load());
    stats["renderTimeRecordSeconds"] = renderRecords_.nanoseconds.load() * 1e-9;  // thread-seconds
    stats["adoptedRenderTimeRecords"] = double(adoptedRecords_);  // of those, inserted into the cache
    stats["lookups"] = double(lookups_.load());
    stats["cacheBytes"] = double(cache_.memoryBytes());
    stats["recordFillSeconds"] = fillSeconds_;
    stats["recordRefinementRounds"] = refinement_ ? refinement_->rounds() : 0;
    stats["recordRefinementSeconds"] = refinement_ ? refinement_->counters().nanoseconds.load() * 1e-9 : 0.0;
    // As the irradiance cache's, of its path-traced records: their mean paths, count and rays.
    stats["recordPathsMean"] = RecordRefinement::meanSamples(cache_);
    stats["pathTracedRecordsInCache"] = double(RecordRefinement::pathTracedCount(cache_));
    stats["recordRays"] = double(preprocessRecords_.pathTracedRays.load() + renderRecords_.pathTracedRays.load() +
                                 (refinement_ ? refinement_->counters().rays.load() : 0));
    // The refinement's budget counts the fill's path-traced rays (record_refinement.h).
    stats["preprocessRecordRays"] = double(preprocessRecords_.pathTracedRays.load());
    stats["renderTimeRecordRays"] = double(renderRecords_.pathTracedRays.load());
    stats["recordPhotons"] = recordPhotons_;
    return stats;
}

}  // namespace gi
