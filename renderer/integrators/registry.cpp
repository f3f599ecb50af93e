// Every integrator with its parameters. The CLI's flags and Hydra's render settings are
// generated from this list, so a parameter exists in one place only.
#include "../integrator.h"
#include "direct.h"
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
