// Every integrator with its parameters. The CLI's flags and Hydra's render settings are
// generated from this list, so a parameter exists in one place only.
#include "../integrator.h"

#include <stdexcept>

#include "../auto_select.h"
#include "adaptive_irradiance_cache.h"
#include "direct.h"
#include "irradiance_cache_integrator.h"
#include "path.h"
#include "photon_final_gather.h"
#include "photon_irradiance_cache.h"
#include "progressive_photon_map.h"

namespace gi {

namespace {

ParamInfo intParam(const char* name, double def, double lo, double hi, const char* description) {
    return ParamInfo{name, "int", def, lo, hi, description};
}

const ParamInfo kPaths = intParam("paths", 1, 1, 65536, "paths traced from each camera sample's first hit");
// Depths default to the safety cap: unbounded in effect, Russian roulette ends paths (kDepthCap).
const ParamInfo kPathDepth = intParam("pathDepth", kDepthCap, 0, kDepthCap,
                                      "maximum scattering vertices of a path (default: unbounded, Russian roulette)");
const ParamInfo kRayDepth = intParam("rayDepth", kDepthCap, 0, kDepthCap,
                                     "maximum specular (mirror/refraction) vertices (default: unbounded)");
const ParamInfo kRouletteDepth =
    intParam("rouletteDepth", 3, 0, 1024, "vertices before Russian roulette may end a path");
const ParamInfo kLightSamples = intParam("lightSamples", 1, 1, 4096, "light samples per shading point");
// Irradiance caching (thesis 3.3.1, 3.3.2). 108 paths as in the thesis's tables 4.1 and 4.5.
const ParamInfo kRecordPaths =
    intParam("paths", 108, 1, 65536, "hemisphere paths per irradiance record (M x N stratified cells)");
const ParamInfo kAccuracy = ParamInfo{"accuracy", "float", 1, 0.01, 100,
                                      "k of the Tabellion-Lamorlette error: higher is more accurate, more records"};
const ParamInfo kMinSpacing = ParamInfo{"minSpacing", "float", 1.5, 0.1, 1000, "smallest record radius, in pixels"};
const ParamInfo kMaxSpacing = ParamInfo{"maxSpacing", "float", 10, 0.1, 10000, "largest record radius, in pixels"};
const ParamInfo kRefineRecords = ParamInfo{
    "refineRecords", "bool", 1, 0, 1,
    "between passes, add hemisphere paths to every path-traced record (as many rays as the passes traced), "
    "so the cache converges as the render goes on (0: records fixed after the fill, as the thesis)"};
const ParamInfo kThreshold = ParamInfo{"threshold", "float", 0.02, 0, 1,
                                       "adaptive refinement: relative luminance change that is discernible (2.38)"};
const ParamInfo kRefinementRounds =
    intParam("refinementRounds", 1000, 0, 100000, "adaptive refinement: most rounds of the refinement queue");

// Photon mapping (thesis 2.4.7, 3.3.4, 3.3.5; 500 000 photons as in tables 4.3-4.15).
const ParamInfo kPhotons = intParam("photons", 500000, 0, 1e12,
                                    "photons emitted for the global photon map (more than 2^24 is clamped, with a warning)");
const ParamInfo kCausticPhotons =
    intParam("causticPhotons", 500000, 0, 1e12, "photons emitted for the caustic map (L S+ D paths); none without specular surfaces");
const ParamInfo kPhotonDepth = intParam("photonDepth", kDepthCap, 0, kDepthCap,
                                        "most reflections of a photon (default: unbounded, Russian roulette absorbs it)");
const ParamInfo kMaxGatherRadius = ParamInfo{"maxGatherRadius", "float", 0, 0, 1e30,
                                             "largest photon density-estimate radius, scene units; 0 = a tenth of the scene's radius"};
const ParamInfo kFinalGatherSamples = intParam("finalGatherSamples", 16, 0, 65536, "final-gather rays per shading point");
const ParamInfo kFinalGatherDepth =
    intParam("finalGatherDepth", kDepthCap, 1, kDepthCap,
             "most vertices of a final-gather path (specular ones continue it; default: unbounded)");
const ParamInfo kPhotonRecordPaths = intParam(
    "paths", 120, 1, 65536, "hemisphere paths of a record where photons are too few (path-traced record; thesis: 120)");

// Every integrator takes it; the renderer applies it to each camera sample (see Renderer).
const ParamInfo kSampleClamp = ParamInfo{
    "sampleClamp", "float", 0, 0, 1e30,
    "clamp each camera sample's luminance to this (0 = off); biased, but removes fireflies"};

PhotonMapSettings photonMapSettings(const IntegratorInfo& info, const ParamSet& p) {
    PhotonMapSettings s;
    s.photons = paramValue(info, p, "photons");
    s.causticPhotons = paramValue(info, p, "causticPhotons");
    s.photonDepth = int(paramValue(info, p, "photonDepth"));
    s.gatherPhotons = int(paramValue(info, p, "gatherPhotons"));
    s.maxGatherRadius = float(paramValue(info, p, "maxGatherRadius"));
    s.rayDepth = int(paramValue(info, p, "rayDepth"));
    return s;
}

IrradianceCacheSettings irradianceCacheSettings(const IntegratorInfo& info, const ParamSet& p) {
    IrradianceCacheSettings s;
    s.record.paths = int(paramValue(info, p, "paths"));
    s.record.pathDepth = int(paramValue(info, p, "pathDepth"));
    s.record.rayDepth = int(paramValue(info, p, "rayDepth"));
    s.record.rouletteDepth = int(paramValue(info, p, "rouletteDepth"));
    s.record.accuracy = float(paramValue(info, p, "accuracy"));
    s.record.minSpacing = float(paramValue(info, p, "minSpacing"));
    s.record.maxSpacing = float(paramValue(info, p, "maxSpacing"));
    s.lightSamples = int(paramValue(info, p, "lightSamples"));
    s.refineRecords = paramValue(info, p, "refineRecords") != 0;
    return s;
}

// The plain and adaptive caches' settings: the records' and their own caustic map's (the photon
// cache's caustic map is one of its photon maps).
IrradianceCacheSettings causticCacheSettings(const IntegratorInfo& info, const ParamSet& p) {
    IrradianceCacheSettings s = irradianceCacheSettings(info, p);
    s.causticPhotons = paramValue(info, p, "causticPhotons");
    s.gatherPhotons = int(paramValue(info, p, "gatherPhotons"));
    return s;
}

std::vector<IntegratorInfo> buildRegistry() {
    std::vector<IntegratorInfo> list;
    IntegratorInfo path{"path", "path tracing with next-event estimation, MIS and Russian roulette",
                        {kPaths, kPathDepth, kRayDepth, kRouletteDepth}, nullptr};
    path.create = [info = path](const ParamSet& p) -> std::unique_ptr<Integrator> {
        return std::make_unique<PathIntegrator>(int(paramValue(info, p, "paths")), int(paramValue(info, p, "pathDepth")),
                                                int(paramValue(info, p, "rayDepth")),
                                                int(paramValue(info, p, "rouletteDepth")));
    };
    list.push_back(path);
    IntegratorInfo direct{"direct", "ray tracing: direct light and specular recursion, no indirect diffuse",
                          {kRayDepth, kLightSamples}, nullptr};
    direct.create = [info = direct](const ParamSet& p) -> std::unique_ptr<Integrator> {
        return std::make_unique<DirectIntegrator>(int(paramValue(info, p, "rayDepth")),
                                                  int(paramValue(info, p, "lightSamples")));
    };
    list.push_back(direct);
    IntegratorInfo irradianceCache{
        "irradianceCache", "ray tracing with indirect diffuse light from an irradiance cache (gradients, T&L error)",
        {kRecordPaths, kPathDepth, kRayDepth, kRouletteDepth, kLightSamples, kAccuracy, kMinSpacing, kMaxSpacing,
         kRefineRecords,
         intParam("causticPhotons", 500000, 0, 1e12,
                  "photons emitted for a caustic map of the light that glass and mirrors focus (L S+ D paths), which "
                  "the records' paths find only by chance; none without specular surfaces or with domes alone "
                  "(0: the records carry it, as the thesis)"),
         intParam("gatherPhotons", 50, 2, 100000, "photons per caustic density estimate (k nearest)")},
        nullptr};
    irradianceCache.create = [info = irradianceCache](const ParamSet& p) -> std::unique_ptr<Integrator> {
        return std::make_unique<IrradianceCacheIntegrator>(causticCacheSettings(info, p));
    };
    list.push_back(irradianceCache);
    IntegratorInfo adaptive{"adaptiveIrradianceCache",
                            "irradiance caching with the adaptive refinement of Krivanek et al. 2006 (parallel, bounded memory)",
                            irradianceCache.params, nullptr};
    adaptive.params.push_back(kThreshold);
    adaptive.params.push_back(kRefinementRounds);
    adaptive.create = [info = adaptive](const ParamSet& p) -> std::unique_ptr<Integrator> {
        AdaptiveRefinementSettings refinement;
        refinement.threshold = float(paramValue(info, p, "threshold"));
        refinement.maxRounds = int(paramValue(info, p, "refinementRounds"));
        return std::make_unique<AdaptiveIrradianceCacheIntegrator>(causticCacheSettings(info, p), refinement);
    };
    list.push_back(adaptive);
    IntegratorInfo finalGather{
        "photonMapFinalGather",
        "photon mapping with final gathering: direct light, caustics from the caustic map, gather rays into the global map",
        {kPhotons, kCausticPhotons, kPhotonDepth, intParam("gatherPhotons", 50, 2, 100000, "photons per density estimate (k nearest)"),
         kMaxGatherRadius, kFinalGatherSamples, kFinalGatherDepth,
         ParamInfo{"gatherDirectLight", "bool", 1, 0, 1,
                   "light-sample the direct light at gather hits, the photon map giving the rest (0: all from the map, as the thesis)"},
         intParam("gatherBounces", 1, 0, kDepthCap,
                  "vertices a gather ray path-traces past its hit before it reads the photon map (0: at the hit, as the thesis)"),
         kRayDepth, kLightSamples},
        nullptr};
    finalGather.create = [info = finalGather](const ParamSet& p) -> std::unique_ptr<Integrator> {
        PhotonFinalGatherSettings s;
        s.photons = photonMapSettings(info, p);
        s.finalGatherSamples = int(paramValue(info, p, "finalGatherSamples"));
        s.finalGatherDepth = int(paramValue(info, p, "finalGatherDepth"));
        s.gatherDirectLight = paramValue(info, p, "gatherDirectLight") != 0;
        s.gatherBounces = int(paramValue(info, p, "gatherBounces"));
        s.rayDepth = int(paramValue(info, p, "rayDepth"));
        s.lightSamples = int(paramValue(info, p, "lightSamples"));
        return std::make_unique<PhotonMapFinalGatherIntegrator>(s);
    };
    list.push_back(finalGather);
    IntegratorInfo photonCache{
        "photonMapIrradianceCache",
        "photon mapping with an irradiance cache whose records are photon-map estimates (path-traced where photons are few)",
        {kPhotons, kCausticPhotons, kPhotonDepth,
         intParam("gatherPhotons", 100, 2, 100000, "photons per density estimate (k nearest)"), kMaxGatherRadius,
         kPhotonRecordPaths, kPathDepth, kRayDepth, kRouletteDepth, kLightSamples, kAccuracy, kMinSpacing, kMaxSpacing,
         kRefineRecords},
        nullptr};
    photonCache.create = [info = photonCache](const ParamSet& p) -> std::unique_ptr<Integrator> {
        PhotonIrradianceCacheSettings s;
        s.photons = photonMapSettings(info, p);
        IrradianceCacheSettings cache = irradianceCacheSettings(info, p);
        s.record = cache.record;
        s.lightSamples = cache.lightSamples;
        s.refineRecords = cache.refineRecords;
        return std::make_unique<PhotonMapIrradianceCacheIntegrator>(s);
    };
    list.push_back(photonCache);
    IntegratorInfo progressive{
        "progressivePhotonMap",
        "progressive photon mapping (stochastic PPM, Knaus-Zwicker form): a new photon map every sample, radii shrinking; "
        "consistent, converges to the right image with samples",
        {intParam("photonsPerPass", 200000, 0, 1e12,
                  "photons traced for each sample's photon map (0: none, the ray-traced part alone)"),
         ParamInfo{"initialRadius", "float", 4, 0.01, 1e6, "density-estimate radius of the first sample, in pixel footprints"},
         ParamInfo{"alpha", "float", 2.0 / 3, 0.01, 1, "radius reduction: r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1)"},
         kPhotonDepth, kRayDepth, kLightSamples},
        nullptr};
    progressive.create = [info = progressive](const ParamSet& p) -> std::unique_ptr<Integrator> {
        ProgressivePhotonMapSettings s;
        s.photonsPerPass = paramValue(info, p, "photonsPerPass");
        s.initialRadius = float(paramValue(info, p, "initialRadius"));
        s.alpha = float(paramValue(info, p, "alpha"));
        s.photonDepth = int(paramValue(info, p, "photonDepth"));
        s.rayDepth = int(paramValue(info, p, "rayDepth"));
        s.lightSamples = int(paramValue(info, p, "lightSamples"));
        return std::make_unique<ProgressivePhotonMapIntegrator>(s);
    };
    list.push_back(progressive);
    // Not an integrator of its own: the renderer's pilot renders choose one (auto_select.h).
    IntegratorInfo automatic{
        kAutoIntegrator,
        "automatic choice: short pilot renders predict every technique's error at the time limit, the best renders",
        {ParamInfo{"autoPilotShare", "float", 0.1, 0.01, 0.5, "share of the time limit spent on pilot renders"},
         ParamInfo{"autoHorizon", "float", 60, 0.1, 1e7,
                   "seconds the choice is made for when the render has no time limit"}},
        nullptr};
    automatic.create = [](const ParamSet&) -> std::unique_ptr<Integrator> {
        throw std::logic_error("'auto' is resolved by the renderer's pilot renders, not created");
    };
    list.push_back(automatic);
    for (IntegratorInfo& info : list) info.params.push_back(kSampleClamp);
    return list;
}

// The thesis's parameter tables: 4.1-4.3 for the Cornell box ("Caixa"), 4.9-4.11 for Sibenik.
// Depth 5 everywhere, the path tracer's paths per sample, and records fixed after the fill (the
// thesis's caches are not refined between passes); the rest are already the defaults
// (108 and 120 record paths, 500 000 photons, 16 final-gather rays), written out so the preset
// keeps them if a default changes.
std::vector<Preset> buildPresets() {
    auto thesis = [](const char* name, const char* description, double pathPaths, double gatherSamples) {
        const double depth = 5;
        Preset p{name, description, {}};
        p.params["path"] = {{"paths", pathPaths}, {"pathDepth", depth}, {"rayDepth", depth}};
        p.params["direct"] = {{"rayDepth", depth}};
        for (const char* cache : {"irradianceCache", "adaptiveIrradianceCache"})
            p.params[cache] = {{"paths", 108}, {"pathDepth", depth}, {"rayDepth", depth}, {"refineRecords", 0},
                               {"causticPhotons", 0}};
        p.params["photonMapFinalGather"] = {{"photons", 500000}, {"causticPhotons", 500000}, {"photonDepth", depth},
                                            {"finalGatherSamples", gatherSamples}, {"finalGatherDepth", depth},
                                            {"gatherDirectLight", 0}, {"gatherBounces", 0},
                                            {"rayDepth", depth}};
        p.params["photonMapIrradianceCache"] = {{"photons", 500000}, {"causticPhotons", 500000}, {"photonDepth", depth},
                                                {"paths", 120}, {"pathDepth", depth}, {"rayDepth", depth},
                                                {"refineRecords", 0}};
        return p;
    };
    return {thesis("thesis", "the thesis's tables 4.1-4.3 (Cornell box): depth 5, 8 paths per path-traced sample, "
                             "16 final-gather rays",
                   8, 16),
            thesis("thesis-sibenik", "the thesis's tables 4.9-4.11 (Sibenik): depth 5, 10 paths per path-traced sample, "
                                     "20 final-gather rays",
                   10, 20)};
}

}  // namespace

const std::vector<Preset>& presets() {
    static const std::vector<Preset> list = buildPresets();  // immutable after first use
    return list;
}

const Preset* findPreset(const std::string& name) {
    for (const Preset& p : presets())
        if (p.name == name) return &p;
    return nullptr;
}

ParamSet withPreset(const std::string& presetName, const std::string& integrator, const ParamSet& chosen) {
    if (presetName.empty()) return chosen;
    const Preset* preset = findPreset(presetName);
    if (!preset) {
        std::string names;
        for (const Preset& p : presets()) names += (names.empty() ? "" : ", ") + p.name;
        throw std::invalid_argument("unknown preset '" + presetName + "' (have: " + names + ")");
    }
    ParamSet merged;
    auto it = preset->params.find(integrator);
    if (it != preset->params.end())
        for (const auto& [name, value] : it->second) merged.set(name, value);
    for (const auto& [name, value] : chosen.values()) merged.set(name, value);  // what the user chose wins
    return merged;
}

const std::vector<IntegratorInfo>& integratorRegistry() {
    static const std::vector<IntegratorInfo> registry = buildRegistry();  // immutable after first use
    return registry;
}

const IntegratorInfo* findIntegrator(const std::string& name) {
    for (const IntegratorInfo& info : integratorRegistry())
        if (info.name == name) return &info;
    return nullptr;
}

double paramValue(const IntegratorInfo& info, const ParamSet& params, const std::string& name) {
    for (const ParamInfo& p : info.params)
        if (p.name == name) {
            double v = params.get(name, p.defaultValue);
            if (!std::isfinite(v)) v = p.defaultValue;
            return std::clamp(v, p.minValue, p.maxValue);
        }
    // Only the registry's own create functions read parameters, by the names they declare.
    throw std::logic_error("integrator " + info.name + " has no parameter '" + name + "'");
}

}  // namespace gi
