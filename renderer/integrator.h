// The integrator interface (thesis 3.1: a preprocess step, then radiance per camera ray) and
// the registry that reflects every integrator's parameters to the CLI and to Hydra.
#pragma once
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "camera.h"
#include "film.h"
#include "sampler.h"
#include "scene.h"

namespace gi {

// Default of every depth parameter (path, ray, photon and final-gather depth): unbounded in
// effect. Russian roulette ends paths; the cap only stops one trapped forever (between two
// mirrors, inside a lossless glass block), and each path it stops is counted and warned about.
inline constexpr int kDepthCap = 1024;

// Ends a path at its depth limit; counts it when the limit is the safety cap.
inline bool depthLimitReached(int depth, int limit, RayStats& stats) {
    if (depth < limit) return false;
    if (limit >= kDepthCap) ++stats.depthCapped;
    return true;
}

struct ParamInfo {
    std::string name;  // camelCase, as in USD render settings
    std::string type;  // "int" | "float" | "bool"
    double defaultValue, minValue, maxValue;
    std::string description;
};

class ParamSet {
public:
    void set(const std::string& name, double value) { values_[name] = value; }
    bool has(const std::string& name) const { return values_.count(name) != 0; }
    double get(const std::string& name, double fallback) const {
        auto it = values_.find(name);
        return it == values_.end() ? fallback : it->second;
    }
    const std::map<std::string, double>& values() const { return values_; }

private:
    std::map<std::string, double> values_;
};

// Seconds on the steady clock since its epoch: the unit of the renderer's deadlines.
double steadySeconds();

// What preprocessing may use: the scene, the view (for view-driven caches), threads and a seed.
struct PreprocessContext {
    const Scene& scene;
    const Camera& camera;
    int width, height;
    uint32_t seed;
    const std::atomic<bool>* cancel;
    // A time-limited render's share for preprocessing: steadySeconds() by which it should be
    // done; 0 = no limit. Work that can stop early (fill phases, refinement rounds) stops when
    // it passes; work that has to be sized up front (photon counts) sizes itself to end by it.
    double deadline = 0;
    // In beginPass: the rays the render's passes have traced so far (a measure of their work
    // that, unlike time, is the same in every run).
    uint64_t passRays = 0;
    // Set by the renderer: counts the scaledDown() calls, for the render's statistics.
    std::atomic<int>* scaledDownCount = nullptr;

    bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }
    bool pastDeadline() const { return deadline > 0 && steadySeconds() >= deadline; }
    // Seconds left before the deadline (infinity without one, 0 once passed).
    double secondsLeft() const;
    // Preprocessing did less than its parameters asked, to keep the time limit: warns through
    // scene.warn ("time limit: " + what) and counts it in the render's statistics.
    void scaledDown(const std::string& what) const;
};

class Integrator {
public:
    virtual ~Integrator() = default;
    virtual void preprocess(const PreprocessContext&) {}
    // Integrators whose work depends on the sample index (a photon map per iteration) get each
    // pass's samples [firstSample, firstSample + count) before its tiles, at most
    // maxSamplesPerPass() of them at once (0: any number; the renderer splits longer passes).
    virtual int maxSamplesPerPass() const { return 0; }
    virtual void beginPass(const PreprocessContext&, int /*firstSample*/, int /*count*/) {}
    // Radiance arriving along -ray.d at ray.o. Fills `aovs` (if given) at the first visible surface.
    virtual Color Li(const Ray& ray, const Scene& scene, Sampler& sampler, RayStats& stats, SampleAovs* aovs) const = 0;
    // Counters the integrator wants reported (records, photons, seconds spent in parts).
    virtual std::map<std::string, double> statistics() const { return {}; }
};

struct IntegratorInfo {
    std::string name;
    std::string description;
    std::vector<ParamInfo> params;
    std::function<std::unique_ptr<Integrator>(const ParamSet&)> create;
};

const std::vector<IntegratorInfo>& integratorRegistry();
const IntegratorInfo* findIntegrator(const std::string& name);

// A named parameter set per integrator (historical settings, e.g. the thesis's tables).
struct Preset {
    std::string name, description;
    std::map<std::string, std::map<std::string, double>> params;  // integrator -> parameter -> value
};
const std::vector<Preset>& presets();
const Preset* findPreset(const std::string& name);
// The preset's parameters for `integrator`, overridden by those the user chose; `chosen` as it
// is for an empty name. Throws std::invalid_argument for an unknown preset.
ParamSet withPreset(const std::string& preset, const std::string& integrator, const ParamSet& chosen);

// Reads a parameter clamped to its declared range, falling back to its default.
double paramValue(const IntegratorInfo& info, const ParamSet& params, const std::string& name);

}  // namespace gi
