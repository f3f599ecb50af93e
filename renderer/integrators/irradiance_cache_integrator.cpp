#include "irradiance_cache_integrator.h"

#include <tbb/parallel_for.h>

#include <chrono>

#include "specular_chain.h"

namespace gi {

namespace {
using Clock = std::chrono::steady_clock;
uint64_t nanosecondsSince(Clock::time_point start) {
    return uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - start).count());
}
// Pixel streams of the fill pass use a sample index the render never reaches.
constexpr uint32_t kFillSampleIndex = 0xfffffff0u;
}  // namespace

IrradianceCacheIntegrator::IrradianceCacheIntegrator(const IrradianceCacheSettings& settings)
    : DirectIntegrator(settings.record.rayDepth, settings.lightSamples),
      settings_(settings),
      recordSampler_(settings.record),
      cache_(settings.record.accuracy),
      refinement_(recordSampler_.layout().cells()) {
    tracesGlossy_ = true;
}

RecordSite IrradianceCacheIntegrator::siteOf(const ShadingPoint& sp) const {
    return RecordSite{sp.si.p, sp.si.ng, recordNormal(sp), sp.wo, footprint_.at(sp.si.p)};
}

void IrradianceCacheIntegrator::beginPreprocess(const PreprocessContext& context) {
    seed_ = context.seed;
    footprint_ = PixelFootprint::of(context.camera);
    const SceneBounds& bounds = context.scene.bounds();
    cache_.reset(bounds.center, bounds.radius);
    buildCausticMap(context);
}

void IrradianceCacheIntegrator::buildCausticMap(const PreprocessContext& context) {
    maps_ = PhotonMaps();
    recordSampler_.readCaustics(CausticPhotons());
    glossyBranchEmitters_ = BranchEmitters::All;
    const Scene& scene = context.scene;
    // Left out where nothing can focus light, and under domes alone (the map leaves them out).
    bool focusedLight = false;
    for (const auto& light : scene.lights()) focusedLight = focusedLight || !light->isDome();
    if (!(settings_.causticPhotons > 0) || !scene.hasSpecularSurfaces() || !focusedLight ||
        !recordSampler_.gathersLight())
        return;
    PhotonMapSettings photons;
    photons.photons = 0;
    photons.causticPhotons = settings_.causticPhotons;
    photons.gatherPhotons = settings_.gatherPhotons;
    photons.photonDepth = settings_.record.pathDepth;
    photons.rayDepth = settings_.record.rayDepth;
    photons.globalKeepsDirectAndCaustic = false;
    photons.causticMapLeavesOutDomes = true;  // the records' paths carry the sky through glass
    buildPhotonMaps(context, photons, maps_);
    if (!maps_.caustic.empty()) {
        recordSampler_.readCaustics(CausticPhotons{&maps_.caustic, settings_.gatherPhotons, maps_.causticRadius,
                                                   kCausticConeFilter, kRecordCausticShare});
        glossyBranchEmitters_ = BranchEmitters::DomesOnly;  // the map, read through the whole BSDF, has the rest
    }
}

Ray IrradianceCacheIntegrator::pixelCentreRay(const PreprocessContext& context, uint32_t pixel,
                                              Sampler& sampler) const {
    int x = int(pixel % uint32_t(context.width)), y = int(pixel / uint32_t(context.width));
    sampler.start(x, y, kFillSampleIndex);
    return context.camera.generateRay(x + 0.5f, y + 0.5f, Vec2(0.5f, 0.5f));
}

void IrradianceCacheIntegrator::preprocess(const PreprocessContext& context) {
    auto start = Clock::now();
    beginPreprocess(context);
    fillFromPixelCentres(context);
    preprocessSeconds_ = nanosecondsSince(start) * 1e-9;
}

void IrradianceCacheIntegrator::fillFromPixelCentres(const PreprocessContext& context) {
    if (!recordSampler_.gathersLight()) return;
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
        // Sites per fixed-size chunk of pixels, concatenated in chunk order: pixel order.
        constexpr size_t kChunk = 64;
        std::vector<std::vector<RecordSite>> chunks((pixels.size() + kChunk - 1) / kChunk);
        tbb::parallel_for(size_t(0), chunks.size(), [&](size_t chunk) {
            Sampler sampler(seed_);
            RayStats stats;
            for (size_t i = chunk * kChunk; i < std::min(pixels.size(), (chunk + 1) * kChunk); ++i) {
                Ray ray = pixelCentreRay(context, pixels[i], sampler);
                forEachDiffuseHit(context.scene, ray, sampler, stats, rayDepth_, [&](const ShadingPoint& sp) {
                    if (!isBlack(sp.bsdf.diffuseReflectance())) chunks[chunk].push_back(siteOf(sp));
                });
            }
        });
        std::vector<RecordSite> sites;
        for (auto& chunk : chunks) sites.insert(sites.end(), chunk.begin(), chunk.end());
        addMissingRecords(context.scene, recordSampler_, seed_, sites, cache_, preprocessRecords_);
    }
}

void IrradianceCacheIntegrator::beginPass(const PreprocessContext& context, int, int) {
    for (const RenderTimeRecords::Entry& e : renderTimeRecords_.take())
        if (!cache_.covers(e.record.p, e.record.n)) {
            cache_.insert(e.record);
            ++adoptedRecords_;
        }
    if (!settings_.refineRecords || !recordSampler_.gathersLight()) return;
    refinement_.beforePass(context, preprocessRecords_.rays.load(), cache_,
                           [&](const RecordSite& site, uint32_t key, uint32_t before, RayStats& stats) {
                               return recordSampler_.sample(context.scene, site, seed_, key, stats, before);
                           });
}

Color IrradianceCacheIntegrator::indirect(const Scene& scene, const ShadingPoint& sp, Sampler& sampler,
                                          RayStats& stats) const {
    Color caustic(0.0f);
    if (!maps_.caustic.empty())
        caustic = maps_.caustic.radiance(sp, scene, settings_.gatherPhotons, maps_.causticRadius, kCausticConeFilter).value;
    Color reflectance = sp.bsdf.diffuseReflectance();
    if (isBlack(reflectance) || !recordSampler_.gathersLight()) return caustic;
    auto start = Clock::now();
    lookups_.fetch_add(1, std::memory_order_relaxed);
    Vec3 n = recordNormal(sp);
    Color E;
    bool found = cache_.interpolate(sp.si.p, n, &E);
    if (!found) {
        found = cache_.interpolate(sp.si.p, n, &E, true);
        if (found) relaxedLookups_.fetch_add(1, std::memory_order_relaxed);
    }
    interpolationNanoseconds_.fetch_add(nanosecondsSince(start), std::memory_order_relaxed);
    if (!found) {
        // Nothing near enough: a record for this sample alone, from a stream keyed by its site.
        auto recordStart = Clock::now();
        RecordSite site = siteOf(sp);
        RayStats recordStats;
        IrradianceRecord record = recordSampler_.sample(scene, site, seed_, IrradianceRecordSampler::streamKey(site), recordStats);
        E = record.E;
        renderTimeRecords_.add(record);
        stats.rays += recordStats.rays;
        renderRecords_.records.fetch_add(1, std::memory_order_relaxed);
        renderRecords_.rays.fetch_add(recordStats.rays, std::memory_order_relaxed);
        renderRecords_.nanoseconds.fetch_add(nanosecondsSince(recordStart), std::memory_order_relaxed);
    }
    return caustic + sp.bsdf.diffuseLobe(sp.woLocal) * E;
}

std::map<std::string, double> IrradianceCacheIntegrator::statistics() const {
    const RecordCounters& refined = refinement_.counters();
    double recordSeconds =
        (preprocessRecords_.nanoseconds.load() + renderRecords_.nanoseconds.load() + refined.nanoseconds.load()) * 1e-9;
    std::map<std::string, double> s = {
        {"records", double(cache_.size())},
        {"recordSamplesClamped", double(recordSampler_.outliersClamped())},
        {"preprocessRecords", double(preprocessRecords_.records.load())},
        {"renderTimeRecords", double(renderRecords_.records.load())},
        {"renderTimeRecordSeconds", renderRecords_.nanoseconds.load() * 1e-9},  // thread-seconds
        {"adoptedRenderTimeRecords", double(adoptedRecords_)},  // of those, inserted into the cache
        {"recordRays", double(preprocessRecords_.rays.load() + renderRecords_.rays.load() + refined.rays.load())},
        {"preprocessRecordRays", double(preprocessRecords_.rays.load())},
        {"renderTimeRecordRays", double(renderRecords_.rays.load())},
        {"recordSeconds", recordSeconds},  // thread-seconds spent computing records
        {"interpolationSeconds", interpolationNanoseconds_.load() * 1e-9},  // thread-seconds in lookups
        {"preprocessSeconds", preprocessSeconds_},
        {"lookups", double(lookups_.load())},
        {"relaxedLookups", double(relaxedLookups_.load())},
        {"hemisphereCells", double(recordSampler_.layout().cells())},
        {"recordRefinementRounds", double(refinement_.rounds())},
        {"recordRefinementSeconds", refined.nanoseconds.load() * 1e-9},  // thread-seconds
        {"recordPathsMean", RecordRefinement::meanSamples(cache_)},
        {"cacheBytes", double(cache_.memoryBytes())},
    };
    for (const auto& [name, value] : maps_.statistics) s[name] = value;
    return s;
}

}  // namespace gi
