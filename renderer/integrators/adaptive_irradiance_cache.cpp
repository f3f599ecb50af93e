#include "adaptive_irradiance_cache.h"

#include <chrono>

#include "../render.h"

namespace gi {

AdaptiveIrradianceCacheIntegrator::AdaptiveIrradianceCacheIntegrator(const IrradianceCacheSettings& settings,
                                                                     const AdaptiveRefinementSettings& refinement)
    : IrradianceCacheIntegrator(settings), refinementSettings_(refinement) {}

void AdaptiveIrradianceCacheIntegrator::preprocess(const PreprocessContext& context) {
    using Clock = std::chrono::steady_clock;
    auto start = Clock::now();
    beginPreprocess(context);
    if (recordSampler_.gathersLight()) {
        ShadingPointStore points;
        points.collect(context, rayDepth_, lightSamples_);
        shadingPoints_ = points.size();
        shadingPointBytes_ = points.memoryBytes();
        AdaptiveRefinement refinement(context.scene, recordSampler_, seed_, footprint_,
                                      PixelPhases(context.width, context.height, settings_.record.maxSpacing), points,
                                      cache_, preprocessRecords_);
        std::vector<uint32_t> all(points.size());
        for (size_t i = 0; i < all.size(); ++i) all[i] = uint32_t(i);
        refinement.cover(all, context.deadline);
        firstFillRecords_ = cache_.size();
        auto refineStart = Clock::now();
        if (context.pastDeadline())  // the render computes the records still missing
            context.scaledDown("adaptive irradiance cache: the first fill reached the preprocessing deadline; no refinement");
        else if (!context.cancelled()) {
            refinement_ = refinement.refine(refinementSettings_, context.cancel, context.deadline);
            if (!refinement_.converged && context.pastDeadline())
                context.scaledDown("adaptive irradiance cache refinement stopped after " +
                                   std::to_string(refinement_.rounds) + " rounds, unconverged");
        }
        refinementSeconds_ = std::chrono::duration<double>(Clock::now() - refineStart).count();
        peakMemoryBytes_ = peakResidentMemoryBytes();  // while the points are still held
    }
    preprocessSeconds_ = std::chrono::duration<double>(Clock::now() - start).count();
}

std::map<std::string, double> AdaptiveIrradianceCacheIntegrator::statistics() const {
    std::map<std::string, double> s = IrradianceCacheIntegrator::statistics();
    s["shadingPoints"] = double(shadingPoints_);
    s["shadingPointBytes"] = double(shadingPointBytes_);
    s["pointIndexBytes"] = double(refinement_.indexBytes);
    s["firstFillRecords"] = double(firstFillRecords_);
    s["refinementRecords"] = double(refinement_.newRecords);
    s["refinementShrinks"] = double(refinement_.shrinks);
    s["refinementRounds"] = double(refinement_.rounds);
    s["refinementPointVisits"] = double(refinement_.pointVisits);
    s["refinementConverged"] = refinement_.converged ? 1 : 0;
    s["refinementSeconds"] = refinementSeconds_;
    s["preprocessPeakMemoryBytes"] = double(peakMemoryBytes_);
    return s;
}

}  // namespace gi
