// Records computed at render time, kept for the passes after (issue 15). A lookup that finds no
// record (a jittered sample on a column or a plant stem between the pixel centres the fill
// visited, a point seen in a mirror) computes a record for that sample alone; on Sibenik at 32
// spp that was 17,475 records of 108 paths each, four times the cache's 4,174, and most of the
// render's time. Every such record is now kept, and before the next pass the records of the
// pass just ended are inserted into the cache, each unless one inserted before it covers it: the
// gap is filled after the first pass that found it. Within a pass the cache does not change, so
// the records a pass computes are a function of the seed; they are inserted in the order of their
// sites, not of the threads that computed them, so the cache stays deterministic.
#pragma once
#include <tbb/concurrent_vector.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <vector>

#include "irradiance_record.h"

namespace gi {

class RenderTimeRecords {
public:
    struct Entry {
        IrradianceRecord record;
        uint32_t surface = 0;  // what the integrator needs besides the record (the photon cache's surface)
    };

    // Safe from any number of threads.
    void add(const IrradianceRecord& record, uint32_t surface = 0) { pending_.push_back(Entry{record, surface}); }

    // The records added since the last call, in the order of their sites.
    std::vector<Entry> take() {
        std::vector<Entry> entries(pending_.begin(), pending_.end());
        pending_.clear();
        auto key = [](const Entry& e) {
            const IrradianceRecord& r = e.record;
            return std::array<uint32_t, 6>{std::bit_cast<uint32_t>(r.p.x), std::bit_cast<uint32_t>(r.p.y),
                                           std::bit_cast<uint32_t>(r.p.z), std::bit_cast<uint32_t>(r.n.x),
                                           std::bit_cast<uint32_t>(r.n.y), std::bit_cast<uint32_t>(r.n.z)};
        };
        std::sort(entries.begin(), entries.end(), [&](const Entry& a, const Entry& b) { return key(a) < key(b); });
        return entries;
    }

private:
    tbb::concurrent_vector<Entry> pending_;
};

}  // namespace gi
