// The irradiance cache: records in insertion order and the octree over them, with the
// Tabellion-Lamorlette weighted, gradient-extrapolated interpolation of formula 2.31.
//
// Threading: lookups are const and run on all threads at once; insert() and changes to a
// record's radius factor happen only between parallel phases, in an order fixed by the
// caller, so the cache's content never depends on thread timing.
#pragma once
#include <vector>

#include "irradiance_record.h"
#include "record_octree.h"

namespace gi {

class IrradianceCache {
public:
    explicit IrradianceCache(float accuracy = 1) : accuracy_(accuracy) {}

    void reset(const Vec3& center, float radius);
    uint32_t insert(const IrradianceRecord& record);
    size_t size() const { return records_.size(); }
    const IrradianceRecord& record(uint32_t id) const { return records_[id]; }
    // Adaptive refinement's a_i (2.39): only shrinks, so the octree's boxes stay conservative.
    void shrinkRadiusFactor(uint32_t id, float factor);
    // Merges `more` (new samples at the record's own site) into record `id`: its irradiance,
    // gradients and sigma become those of all its samples; position, radius and distances stay,
    // so the octree holds. Distinct ids may be refined on several threads at once.
    void addSamples(uint32_t id, const IrradianceRecord& more);
    // A new estimate of a record that is not path traced (samples == 0: a photon estimate), from
    // more photons: its irradiance and sigma; position, radius and distances stay.
    void reestimate(uint32_t id, const Color& E, float sigma);
    float accuracy() const { return accuracy_; }

    struct Contribution {
        uint32_t record;
        float weight;
        Color E;  // the record extrapolated to the lookup point
    };
    // Every record valid at (p, n), in insertion order, with its weight and extrapolation.
    void gather(const Vec3& p, const Vec3& n, std::vector<Contribution>& out, bool relaxed = false) const;
    // 2.31. False (E untouched) when no record is valid at (p, n).
    bool interpolate(const Vec3& p, const Vec3& n, Color* E, bool relaxed = false) const;
    bool covers(const Vec3& p, const Vec3& n) const;

    size_t memoryBytes() const;

private:
    template <class Visit>
    void forEachValid(const Vec3& p, const Vec3& n, bool relaxed, Visit&& visit) const;

    float accuracy_;
    std::vector<IrradianceRecord> records_;
    RecordOctree octree_;
};

}  // namespace gi
