#include "instancer.h"

#include <algorithm>

#include "pxr/base/gf/quatd.h"
#include "pxr/base/gf/quatf.h"
#include "pxr/base/gf/quath.h"
#include "pxr/base/gf/rotation.h"
#include "pxr/base/gf/vec3f.h"
#include "pxr/base/gf/vec4f.h"
#include "pxr/base/vt/array.h"
#include "pxr/imaging/hd/renderIndex.h"
#include "pxr/imaging/hd/sceneDelegate.h"
#include "pxr/imaging/hd/timeSampleArray.h"
#include "pxr/imaging/hd/tokens.h"

PXR_NAMESPACE_OPEN_SCOPE

HdGiInstancer::HdGiInstancer(HdSceneDelegate* delegate, SdfPath const& id) : HdInstancer(delegate, id) {}

void HdGiInstancer::Sync(HdSceneDelegate* delegate, HdRenderParam*, HdDirtyBits* dirtyBits) {
    _UpdateInstancer(delegate, dirtyBits);
    SdfPath const& id = GetId();
    if (!HdChangeTracker::IsAnyPrimvarDirty(*dirtyBits, id) && !HdChangeTracker::IsTransformDirty(*dirtyBits, id)) return;
    std::lock_guard<std::mutex> lock(_mutex);
    _names.clear();
    for (HdPrimvarDescriptor const& pv : delegate->GetPrimvarDescriptors(id, HdInterpolationInstance))
        _names.push_back(pv.name);
    _stale = true;
}

// Sampled when an rprim first asks (its sync, after this instancer's), over the interval it asks
// for: a changed shutter resyncs every rprim, not the instancers.
void HdGiInstancer::_Sample(GfVec2f interval) {
    if (!_stale && interval == _sampledInterval) return;
    HdSceneDelegate* delegate = GetDelegate();
    SdfPath const& id = GetId();
    _primvars.clear();
    for (TfToken const& name : _names) {
        HdTimeSampleArray<VtValue, 4> samples;
        delegate->SamplePrimvar(id, name, interval[0], interval[1], &samples);
        Series& series = _primvars[name];
        series.times.assign(samples.times.begin(), samples.times.begin() + samples.count);
        series.values.assign(samples.values.begin(), samples.values.begin() + samples.count);
        if (series.values.empty()) {  // a delegate without samples: the frame's value
            series.times = {0.0f};
            series.values = {delegate->Get(id, name)};
        }
    }
    HdTimeSampleArray<GfMatrix4d, 4> transform;
    delegate->SampleInstancerTransform(id, interval[0], interval[1], &transform);
    _transformTimes.assign(transform.times.begin(), transform.times.begin() + transform.count);
    _transformSamples.assign(transform.values.begin(), transform.values.begin() + transform.count);
    if (_transformSamples.empty()) {
        _transformTimes = {0.0f};
        _transformSamples = {delegate->GetInstancerTransform(id)};
    }
    _sampledInterval = interval;
    _stale = false;
}

namespace {

// Where `t` falls among increasing `times`: sample `index`, and the fraction of the way to the next.
struct Bracket {
    size_t index = 0;
    double fraction = 0;
};
Bracket BracketOf(std::vector<float> const& times, float t) {
    if (times.size() < 2 || t <= times.front()) return {};
    if (t >= times.back()) return {times.size() - 1, 0.0};
    size_t i = size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
    return {i, double(t - times[i]) / double(times[i + 1] - times[i])};
}

bool Rotation(VtValue const& value, size_t i, GfMatrix4d* m) {
    auto set = [&](GfQuatd q) {
        m->SetRotate(q);
        return true;
    };
    if (value.IsHolding<VtQuathArray>()) {
        auto const& a = value.UncheckedGet<VtQuathArray>();
        if (i < a.size()) return set(GfQuatd(a[i]));
    } else if (value.IsHolding<VtQuatfArray>()) {
        auto const& a = value.UncheckedGet<VtQuatfArray>();
        if (i < a.size()) return set(GfQuatd(a[i]));
    } else if (value.IsHolding<VtQuatdArray>()) {
        auto const& a = value.UncheckedGet<VtQuatdArray>();
        if (i < a.size()) return set(a[i]);
    } else if (value.IsHolding<VtVec4fArray>()) {  // (real, i, j, k), hdEmbree's convention
        auto const& a = value.UncheckedGet<VtVec4fArray>();
        if (i < a.size()) return set(GfQuatd(a[i][0], a[i][1], a[i][2], a[i][3]));
    }
    return false;
}

bool Vector(VtValue const& value, size_t i, GfVec3d* v) {
    if (value.IsHolding<VtVec3fArray>()) {
        auto const& a = value.UncheckedGet<VtVec3fArray>();
        if (i < a.size()) return *v = GfVec3d(a[i]), true;
    } else if (value.IsHolding<VtVec3dArray>()) {
        auto const& a = value.UncheckedGet<VtVec3dArray>();
        if (i < a.size()) return *v = a[i], true;
    } else if (value.IsHolding<VtVec3hArray>()) {
        auto const& a = value.UncheckedGet<VtVec3hArray>();
        if (i < a.size()) return *v = GfVec3d(a[i]), true;
    }
    return false;
}

}  // namespace

std::vector<float> HdGiInstancer::SampleTimes(GfVec2f interval) {
    std::vector<float> times;
    {
        std::lock_guard<std::mutex> lock(_mutex);
        _Sample(interval);
        times = _transformTimes;
        for (auto const& [name, series] : _primvars) times.insert(times.end(), series.times.begin(), series.times.end());
    }
    if (!GetParentId().IsEmpty())
        if (auto* parent = dynamic_cast<HdGiInstancer*>(GetDelegate()->GetRenderIndex().GetInstancer(GetParentId()))) {
            std::vector<float> more = parent->SampleTimes(interval);
            times.insert(times.end(), more.begin(), more.end());
        }
    std::sort(times.begin(), times.end());
    times.erase(std::unique(times.begin(), times.end()), times.end());
    return times;
}

std::vector<GfMatrix4d> HdGiInstancer::ComputeInstanceTransforms(SdfPath const& prototypeId, GfVec2f interval, float time) {
    HdSceneDelegate* delegate = GetDelegate();
    VtIntArray indices = delegate->GetInstanceIndices(GetId(), prototypeId);
    std::vector<GfMatrix4d> transforms(indices.size());
    {
        std::lock_guard<std::mutex> lock(_mutex);
        _Sample(interval);
        Bracket at = BracketOf(_transformTimes, time);
        GfMatrix4d instancerTransform = _transformSamples[at.index];
        if (at.fraction > 0)
            instancerTransform = instancerTransform * (1 - at.fraction) + _transformSamples[at.index + 1] * at.fraction;
        // Each primvar at `time`: its samples either side, blended (rotations along the arc).
        struct Blend {
            VtValue const* a = nullptr;
            VtValue const* b = nullptr;
            double f = 0;
        };
        auto find = [&](TfToken const& name) -> Blend {
            auto it = _primvars.find(name);
            if (it == _primvars.end() || it->second.values.empty()) return {};
            Bracket br = BracketOf(it->second.times, time);
            Blend blend{&it->second.values[br.index], nullptr, br.fraction};
            if (br.fraction > 0) blend.b = &it->second.values[br.index + 1];
            return blend;
        };
        auto vectorAt = [](Blend const& v, size_t i, GfVec3d* out) {
            if (!v.a || !Vector(*v.a, i, out)) return false;
            GfVec3d next;
            if (v.b && Vector(*v.b, i, &next)) *out = *out * (1 - v.f) + next * v.f;
            return true;
        };
        auto rotationAt = [](Blend const& v, size_t i, GfMatrix4d* out) {
            if (!v.a || !Rotation(*v.a, i, out)) return false;
            GfMatrix4d next;
            if (v.b && Rotation(*v.b, i, &next))
                out->SetRotate(GfSlerp(v.f, out->ExtractRotationQuat(), next.ExtractRotationQuat()));
            return true;
        };
        auto matrixAt = [](Blend const& v, size_t i, GfMatrix4d* out) {
            auto get = [i](VtValue const* value, GfMatrix4d* m) {
                if (!value || !value->IsHolding<VtMatrix4dArray>() || i >= value->UncheckedGet<VtMatrix4dArray>().size())
                    return false;
                *m = value->UncheckedGet<VtMatrix4dArray>()[i];
                return true;
            };
            if (!get(v.a, out)) return false;
            GfMatrix4d next;
            if (get(v.b, &next)) *out = *out * (1 - v.f) + next * v.f;
            return true;
        };
        Blend translate = find(HdInstancerTokens->instanceTranslations);
        Blend rotate = find(HdInstancerTokens->instanceRotations);
        Blend scale = find(HdInstancerTokens->instanceScales);
        Blend matrix = find(HdInstancerTokens->instanceTransforms);
        for (size_t k = 0; k < indices.size(); ++k) {
            size_t i = size_t(indices[k]);
            // Row-vector convention: scale, then rotate, then translate, then the instancer.
            GfMatrix4d local(1.0), m(1.0);
            GfVec3d v;
            if (vectorAt(scale, i, &v)) local = local * m.SetScale(v);
            if (rotationAt(rotate, i, &m)) local = local * m;
            if (vectorAt(translate, i, &v)) local = local * GfMatrix4d(1.0).SetTranslate(v);
            if (matrixAt(matrix, i, &m)) local = m * local;
            transforms[k] = local * instancerTransform;
        }
    }
    if (GetParentId().IsEmpty()) return transforms;
    auto* parent = dynamic_cast<HdGiInstancer*>(delegate->GetRenderIndex().GetInstancer(GetParentId()));
    if (!parent) return transforms;
    std::vector<GfMatrix4d> parents = parent->ComputeInstanceTransforms(GetId(), interval, time);
    std::vector<GfMatrix4d> nested;
    nested.reserve(parents.size() * transforms.size());
    for (GfMatrix4d const& p : parents)
        for (GfMatrix4d const& t : transforms) nested.push_back(t * p);
    return nested;
}

bool HdGiRprimInstances(HdSceneDelegate* delegate, SdfPath const& instancerId, SdfPath const& rprimId,
                        GfVec2f interval, std::vector<GfMatrix4d>* transforms, std::vector<float>* times,
                        std::vector<std::vector<GfMatrix4d>>* samples) {
    transforms->clear();
    times->clear();
    samples->clear();
    if (instancerId.IsEmpty()) return false;
    HdRenderIndex& index = delegate->GetRenderIndex();
    HdInstancer::_SyncInstancerAndParents(index, instancerId);
    auto* instancer = dynamic_cast<HdGiInstancer*>(index.GetInstancer(instancerId));
    if (!instancer) return true;
    *transforms = instancer->ComputeInstanceTransforms(rprimId, interval, 0.0f);
    std::vector<float> sampleTimes = instancer->SampleTimes(interval);
    if (sampleTimes.size() < 2) return true;
    *times = sampleTimes;
    for (float t : sampleTimes) samples->push_back(instancer->ComputeInstanceTransforms(rprimId, interval, t));
    return true;
}

PXR_NAMESPACE_CLOSE_SCOPE
