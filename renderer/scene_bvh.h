// The Scene's Embree objects that consecutive scenes share (Scene::reuseBvhOf): those of a frame
// sequence, or of an interactive session's edits. Internal to scene.cpp, scene_queries.cpp and scene_reuse.cpp.
#pragma once
#include <atomic>

#include "scene.h"

namespace gi {

struct Scene::EmbreeDevice {
    RTCDevice device = nullptr;
    // The scene Embree's errors are warned to: the newest scene using the device.
    std::atomic<const Scene*> reporter{nullptr};
    EmbreeDevice();
    ~EmbreeDevice() { rtcReleaseDevice(device); }
};

struct Scene::Bvh {
    RTCScene rtc = nullptr;
    std::vector<std::string> names;      // the shapes', by geometry id
    std::vector<uint64_t> fingerprints;  // the shapes', by geometry id (Scene::fingerprint)
    size_t primitives = 0;               // triangles and spheres
    std::vector<size_t> geometryPrimitives;  // by geometry id
    std::vector<Bounds> geometryBounds;      // by geometry id (Scene::growByShape)
    std::shared_ptr<const SphereStore> spheres;  // its sphere geometries' data: outlives `rtc`
    Bvh() = default;
    Bvh(const Bvh&) = delete;
    Bvh& operator=(const Bvh&) = delete;
    ~Bvh() {
        if (rtc) rtcReleaseScene(rtc);
    }
};

struct Scene::Previous {
    std::map<std::string, uint64_t> topFingerprints;
    std::shared_ptr<const Bvh> staticBvh;
    std::shared_ptr<const Bvh> topLevel;  // its top level, when it held static shapes alone (topLevelAsBvh)
    bool masks = false;                   // BvhReuse::Edits: a kept static BVH may mask shapes
    std::map<std::string, std::shared_ptr<const Bvh>> prototypes;  // by name
};

}  // namespace gi
