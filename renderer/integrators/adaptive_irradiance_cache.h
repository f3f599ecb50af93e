// Irradiance caching with adaptive refinement (Krivanek et al. 2006; thesis 2.4.5, 3.3.2):
// as the thesis's implementation, a first pass at one sample per pixel stores the shading
// points, the cache is filled over them and refined (adaptive_refinement.h), and the normal
// irradiance-cache render then runs on that cache. Unlike the thesis, the refinement runs
// in parallel and its memory stays bounded (compact points, shading_point_store.h).
#pragma once
#include "adaptive_refinement.h"
#include "irradiance_cache_integrator.h"

namespace gi {

class AdaptiveIrradianceCacheIntegrator : public IrradianceCacheIntegrator {
public:
    AdaptiveIrradianceCacheIntegrator(const IrradianceCacheSettings& settings,
                                      const AdaptiveRefinementSettings& refinement);
    void preprocess(const PreprocessContext& context) override;
    std::map<std::string, double> statistics() const override;

private:
    AdaptiveRefinementSettings refinementSettings_;
    RefinementStatistics refinement_;
    size_t shadingPoints_ = 0, shadingPointBytes_ = 0;
    uint64_t firstFillRecords_ = 0;
    double refinementSeconds_ = 0;
    size_t peakMemoryBytes_ = 0;
};

}  // namespace gi
