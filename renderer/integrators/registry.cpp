// Every integrator with its parameters. The CLI's flags and Hydra's render settings are
// generated from this list, so a parameter exists in one place only.
#include "../integrator.h"
#include "adaptive_irradiance_cache.h"
#include "direct.h"
#include "irradiance_cache_integrator.h"
#include "path.h"

namespace gi {

namespace {

ParamInfo intParam(const char* name, double def, double lo, double hi, const char* description) {
    return ParamInfo{name, "int", def, lo, hi, description};
}

const ParamInfo kPaths = intParam("paths", 1, 1, 65536, "paths traced from each camera sample's first hit");
const ParamInfo kPathDepth = intParam("pathDepth", 5, 0, 1024, "maximum scattering vertices of a path");
const ParamInfo kRayDepth = intParam("rayDepth", 5, 0, 1024, "maximum specular (mirror/refraction) vertices");
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
const ParamInfo kThreshold = ParamInfo{"threshold", "float", 0.02, 0, 1,
                                       "adaptive refinement: relative luminance change that is discernible (2.38)"};
const ParamInfo kRefinementRounds =
    intParam("refinementRounds", 1000, 0, 100000, "adaptive refinement: most rounds of the refinement queue");

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
        {kRecordPaths, kPathDepth, kRayDepth, kRouletteDepth, kLightSamples, kAccuracy, kMinSpacing, kMaxSpacing},
        nullptr};
    irradianceCache.create = [info = irradianceCache](const ParamSet& p) -> std::unique_ptr<Integrator> {
        return std::make_unique<IrradianceCacheIntegrator>(irradianceCacheSettings(info, p));
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
        return std::make_unique<AdaptiveIrradianceCacheIntegrator>(irradianceCacheSettings(info, p), refinement);
    };
    list.push_back(adaptive);
    return list;
}

}  // namespace

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
    return 0;
}

}  // namespace gi
