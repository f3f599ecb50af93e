#include "irradiance_cache.h"

#include <algorithm>
#include <cmath>

namespace gi {

void IrradianceCache::reset(const Vec3& center, float radius) {
    records_.clear();
    octree_.reset(center, radius);
}

uint32_t IrradianceCache::insert(const IrradianceRecord& record) {
    uint32_t id = uint32_t(records_.size());
    records_.push_back(record);
    // Indexed by its largest possible influence: a relaxed lookup must find it too.
    octree_.insert(id, record.p, record.influenceRadius() + record.footprint);
    return id;
}

void IrradianceCache::shrinkRadiusFactor(uint32_t id, float factor) {
    records_[id].radiusFactor = std::clamp(factor, 0.0f, records_[id].radiusFactor);
}

void IrradianceCache::addSamples(uint32_t id, const IrradianceRecord& more) {
    IrradianceRecord& r = records_[id];
    const float a = float(r.samples), b = float(more.samples), total = a + b;
    if (!(b > 0)) return;
    const float wa = a / total, wb = b / total;
    r.E = r.E * wa + more.E * wb;
    for (int c = 0; c < 3; ++c) {
        r.rotationGradient[c] = r.rotationGradient[c] * wa + more.rotationGradient[c] * wb;
        r.translationGradient[c] = r.translationGradient[c] * wa + more.translationGradient[c] * wb;
    }
    r.sigma = std::sqrt(wa * wa * r.sigma * r.sigma + wb * wb * more.sigma * more.sigma);
    r.samples += more.samples;
}

void IrradianceCache::reestimate(uint32_t id, const Color& E, float sigma) {
    records_[id].E = E;
    records_[id].sigma = sigma;
}

template <class Visit>
void IrradianceCache::forEachValid(const Vec3& p, const Vec3& n, bool relaxed, Visit&& visit) const {
    octree_.forEachCandidate(p, [&](uint32_t id) {
        const IrradianceRecord& r = records_[id];
        float w = r.weight(p, n, accuracy_, relaxed);
        if (w > 0) visit(id, r, w);
    });
}

void IrradianceCache::gather(const Vec3& p, const Vec3& n, std::vector<Contribution>& out, bool relaxed) const {
    out.clear();
    forEachValid(p, n, relaxed, [&](uint32_t id, const IrradianceRecord& r, float w) {
        out.push_back({id, w, r.extrapolate(p, n)});
    });
    // The octree visits records by node; insertion order makes the sum's rounding reproducible
    // and independent of how the octree happens to be split.
    std::sort(out.begin(), out.end(), [](const Contribution& a, const Contribution& b) { return a.record < b.record; });
}

bool IrradianceCache::interpolate(const Vec3& p, const Vec3& n, Color* E, bool relaxed) const {
    // Summed in octree order: that order is a function of the (deterministic) insertion
    // sequence, so results are reproducible without sorting.
    Color weighted(0.0f);
    float weightSum = 0;
    forEachValid(p, n, relaxed, [&](uint32_t, const IrradianceRecord& r, float w) {
        weighted += r.extrapolate(p, n) * w;
        weightSum += w;
    });
    if (!(weightSum > 0)) return false;
    *E = weighted / weightSum;
    return true;
}

bool IrradianceCache::covers(const Vec3& p, const Vec3& n) const {
    bool found = false;
    forEachValid(p, n, false, [&](uint32_t, const IrradianceRecord&, float) { found = true; });
    return found;
}

size_t IrradianceCache::memoryBytes() const {
    return records_.capacity() * sizeof(IrradianceRecord) + octree_.memoryBytes();
}

}  // namespace gi
