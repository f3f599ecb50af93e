#include "light.h"

#include "area_light.h"

#include "material.h"
#include "moving_light.h"

namespace gi {

namespace {

Color baseRadiance(const LightDesc& d) { return d.color * (d.intensity * std::exp2(d.exposure)); }

// A unit direction between unit directions a and b (a moving light's normal between two steps);
// a where they are opposite (no direction between).
Vec3 directionBetween(const Vec3& a, const Vec3& b, float f) {
    Vec3 v = lerp(a, b, f);
    return lengthSquared(v) > 1e-12f ? normalize(v) : a;
}

class RectLight : public AreaLight {
public:
    RectLight(const Vec3& p0, const Vec3& e1, const Vec3& e2, const Vec3& n, Color L) : p0_(p0), e1_(e1), e2_(e2), n_(n) {
        L_ = L;
        area_ = length(cross(e1, e2));
        rectangular_ = std::fabs(dot(e1, e2)) <= 1e-4f * length(e1) * length(e2);  // not sheared
        center_ = p0 + (e1 + e2) * 0.5f;
        diagonalSquared_ = lengthSquared(e1 + e2);
        plane_ = cross(e1, e2);
        e1Squared_ = dot(e1, e1);
        e2Squared_ = dot(e2, e2);
    }
    static RectLight between(const RectLight& a, const RectLight& b, float f) {
        return RectLight(lerp(a.p0_, b.p0_, f), lerp(a.e1_, b.e1_, f), lerp(a.e2_, b.e2_, f),
                         directionBetween(a.n_, b.n_, f), lerp(a.L_, b.L_, f));
    }
    // Directions uniform over the solid angle the rect subtends (sampling.h): a point beside a
    // large rect light (a wall next to a window) gets none of the 1/d^2 spikes of area sampling.
    // Far rects (below), tiny solid angles (float trouble), near-hemispheres and sheared rects
    // sample by area, as pbrt-v4 does for the last three; pdf() decides the same way.
    LightSample sample(const Vec3& ref, Vec2 u, float time) const override {
        if (!(dot(ref - p0_, n_) > 0)) return {};  // behind the one-sided light
        if (!near(ref)) return AreaLight::sample(ref, u, time);
        SphericalRectangle rect(ref, p0_, e1_, e2_);
        if (!sampledBySolidAngle(rect)) return AreaLight::sample(ref, u, time);
        Vec3 d = rect.sample(u) - ref;
        float dist = length(d);
        LightSample ls;
        if (!(dist > 0)) return ls;
        ls.wi = d / dist;
        ls.distance = dist;
        ls.pdf = 1 / rect.solidAngle;
        ls.Li = L_;
        return ls;
    }
    SurfacePoint samplePoint(Vec2 u) const override { return {p0_ + e1_ * u.x + e2_ * u.y, n_}; }
    Vec3 normalCone(float* cosThetaO) const override {
        *cosThetaO = 1;
        return n_;
    }
    float area() const override { return area_; }
    float pdf(const Vec3& ref, const Vec3& wi, float t, float time) const override {
        if (!(dot(ref - p0_, n_) > 0)) return 0;
        if (near(ref)) {
            SphericalRectangle rect(ref, p0_, e1_, e2_);
            if (sampledBySolidAngle(rect)) return 1 / rect.solidAngle;
        }
        return areaToSolidAngle(1 / area_, t, dot(-wi, n_));
    }
    Color radiance(const Vec3& wi, float time) const override { return dot(-wi, n_) > 0 ? L_ : Color(0); }
    float intersect(const Ray& r) const override {
        float denom = dot(r.d, plane_);
        if (std::fabs(denom) < 1e-20f) return kInf;
        float t = dot(p0_ - r.o, plane_) / denom;
        if (!(t > r.tMin && t < r.tMax)) return kInf;
        Vec3 q = r.o + r.d * t - p0_;
        float a = dot(q, e1_) / e1Squared_, b = dot(q, e2_) / e2Squared_;
        return (a >= 0 && a <= 1 && b >= 0 && b <= 1) ? t : kInf;
    }
    bool shapeBounds(Vec3* lo, Vec3* hi) const override {
        *lo = *hi = p0_;
        for (Vec3 p : {p0_ + e1_, p0_ + e2_, p0_ + e1_ + e2_}) {
            *lo = vmin(*lo, p);
            *hi = vmax(*hi, p);
        }
        return true;
    }

private:
    // Whether the rect is near enough for solid-angle sampling to pay: its diagonal longer than
    // kNearDiagonal times the distance to its centre (a wall beside a window). Farther, area
    // sampling's solid-angle density d^2 / cos varies over the rect by a bounded factor and
    // skips the spherical rectangle's trigonometry. Measured on the Cornell box's path tracer
    // (96x96, 128 spp, one thread, four seeds): the same variance to 0.05% (caustics dominate
    // it), 20% less CPU time than solid-angle sampling everywhere.
    static constexpr float kNearDiagonal = 1.0f;
    bool near(const Vec3& ref) const {
        return rectangular_ && diagonalSquared_ > kNearDiagonal * kNearDiagonal * lengthSquared(center_ - ref);
    }
    bool sampledBySolidAngle(const SphericalRectangle& rect) const {
        return rectangular_ && rect.solidAngle > 3e-4f && rect.solidAngle < 6.22f;
    }
    Vec3 p0_, e1_, e2_, n_, center_;
    Vec3 plane_;  // e1 x e2, and below their squared lengths: every ray tests the rect (intersect)
    float area_, diagonalSquared_ = 0, e1Squared_ = 0, e2Squared_ = 0;
    bool rectangular_ = true;
};

class DiskLight : public AreaLight {
public:
    DiskLight(const Vec3& c, const Vec3& n, float r, Color L) : c_(c), frame_(n), r_(r) { L_ = L; }
    static DiskLight between(const DiskLight& a, const DiskLight& b, float f) {
        return DiskLight(lerp(a.c_, b.c_, f), directionBetween(a.frame_.n, b.frame_.n, f), a.r_ * (1 - f) + b.r_ * f,
                         lerp(a.L_, b.L_, f));
    }
    Vec3 normalCone(float* cosThetaO) const override {
        *cosThetaO = 1;
        return frame_.n;
    }
    SurfacePoint samplePoint(Vec2 u) const override {
        Vec2 d = sampleConcentricDisk(u);
        return {c_ + frame_.s * (d.x * r_) + frame_.t * (d.y * r_), frame_.n};
    }
    float area() const override { return kPi * r_ * r_; }
    float pdf(const Vec3& ref, const Vec3& wi, float t, float time) const override {
        return areaToSolidAngle(1 / area(), t, dot(-wi, frame_.n));
    }
    Color radiance(const Vec3& wi, float time) const override { return dot(-wi, frame_.n) > 0 ? L_ : Color(0); }
    float intersect(const Ray& r) const override {
        float denom = dot(r.d, frame_.n);
        if (std::fabs(denom) < 1e-20f) return kInf;
        float t = dot(c_ - r.o, frame_.n) / denom;
        if (!(t > r.tMin && t < r.tMax)) return kInf;
        return lengthSquared(r.o + r.d * t - c_) <= r_ * r_ ? t : kInf;
    }
    bool shapeBounds(Vec3* lo, Vec3* hi) const override {
        *lo = c_ - Vec3(r_);
        *hi = c_ + Vec3(r_);
        return true;
    }

private:
    Vec3 c_;
    Frame frame_;
    float r_;
};

// Solves |o + t d - c|^2 = r^2 for the nearest t in (tMin, tMax).
float intersectSphere(const Ray& r, const Vec3& c, float radius) {
    Vec3 oc = r.o - c;
    float b = dot(oc, r.d), cc = dot(oc, oc) - radius * radius, a = dot(r.d, r.d);
    float disc = b * b - a * cc;
    if (disc < 0) return kInf;
    float sq = std::sqrt(disc);
    float t0 = (-b - sq) / a, t1 = (-b + sq) / a;
    if (t0 > r.tMin && t0 < r.tMax) return t0;
    if (t1 > r.tMin && t1 < r.tMax) return t1;
    return kInf;
}

class SphereLight : public AreaLight {
public:
    SphereLight(const Vec3& c, float r, Color L) : c_(c), r_(r) { L_ = L; }
    static SphereLight between(const SphereLight& a, const SphereLight& b, float f) {
        return SphereLight(lerp(a.c_, b.c_, f), a.r_ * (1 - f) + b.r_ * f, lerp(a.L_, b.L_, f));
    }
    SurfacePoint samplePoint(Vec2 u) const override {
        Vec3 n = sampleUniformSphere(u);
        return {c_ + n * r_, n};
    }
    float area() const override { return 4 * kPi * r_ * r_; }
    // Samples the cone the sphere subtends (far less noise than area sampling).
    LightSample sample(const Vec3& ref, Vec2 u, float time) const override {
        float d2 = lengthSquared(ref - c_);
        if (d2 <= r_ * r_ * 1.0001f) return AreaLight::sample(ref, u, time);
        float sin2 = r_ * r_ / d2, cosMax = safeSqrt(1 - sin2);
        Frame f(normalize(c_ - ref));
        LightSample ls;
        ls.wi = f.toWorld(sampleUniformCone(u, cosMax));
        Ray ray{ref, ls.wi, 0, kInf};
        float t = intersectSphere(ray, c_, r_);
        if (!std::isfinite(t)) t = std::sqrt(std::max(0.0f, d2 - r_ * r_));  // grazing: tangent distance
        ls.distance = t;
        ls.pdf = uniformConePdfFromSin2(sin2);
        ls.Li = ls.pdf > 0 ? L_ : Color(0.0f);
        return ls;
    }
    float pdf(const Vec3& ref, const Vec3& wi, float t, float time) const override {
        float d2 = lengthSquared(ref - c_);
        if (d2 <= r_ * r_ * 1.0001f) {
            Vec3 p = ref + wi * t;
            return areaToSolidAngle(1 / area(), t, dot(-wi, normalize(p - c_)));
        }
        return uniformConePdfFromSin2(r_ * r_ / d2);
    }
    Color radiance(const Vec3& wi, float time) const override { return L_; }
    float intersect(const Ray& r) const override { return intersectSphere(r, c_, r_); }
    bool shapeBounds(Vec3* lo, Vec3* hi) const override {
        *lo = c_ - Vec3(r_);
        *hi = c_ + Vec3(r_);
        return true;
    }

private:
    Vec3 c_;
    float r_;
};

class CylinderLight : public AreaLight {
public:
    CylinderLight(const Vec3& c, const Vec3& axis, float halfLength, float r, Color L)
        : c_(c), frame_(normalize(axis)), h_(halfLength), r_(r) {
        L_ = L;
    }
    static CylinderLight between(const CylinderLight& a, const CylinderLight& b, float f) {
        Vec3 axis = lerp(a.frame_.n * a.h_, b.frame_.n * b.h_, f);  // half the cylinder, along its axis
        float h = length(axis);
        if (!(h > 0)) return a;  // turned end over end: no axis between
        return CylinderLight(lerp(a.c_, b.c_, f), axis, h, a.r_ * (1 - f) + b.r_ * f, lerp(a.L_, b.L_, f));
    }
    SurfacePoint samplePoint(Vec2 u) const override {
        float phi = 2 * kPi * u.y;
        Vec3 n = frame_.s * std::cos(phi) + frame_.t * std::sin(phi);
        return {c_ + frame_.n * ((2 * u.x - 1) * h_) + n * r_, n};
    }
    float area() const override { return 2 * kPi * r_ * 2 * h_; }
    float pdf(const Vec3& ref, const Vec3& wi, float t, float time) const override {
        Vec3 p = ref + wi * t - c_;
        Vec3 radial = p - frame_.n * dot(p, frame_.n);
        return areaToSolidAngle(1 / area(), t, dot(-wi, normalize(radial)));
    }
    Color radiance(const Vec3& wi, float time) const override { return L_; }
    float intersect(const Ray& r) const override {
        Vec3 o = frame_.toLocal(r.o - c_), d = frame_.toLocal(r.d);  // axis = local z
        float a = d.x * d.x + d.y * d.y, b = o.x * d.x + o.y * d.y, cc = o.x * o.x + o.y * o.y - r_ * r_;
        if (a < 1e-20f) return kInf;
        float disc = b * b - a * cc;
        if (disc < 0) return kInf;
        float sq = std::sqrt(disc);
        for (float t : {(-b - sq) / a, (-b + sq) / a})
            if (t > r.tMin && t < r.tMax && std::fabs(o.z + t * d.z) <= h_) return t;
        return kInf;
    }
    bool shapeBounds(Vec3* lo, Vec3* hi) const override {
        *lo = c_ - Vec3(h_ + r_);
        *hi = c_ + Vec3(h_ + r_);
        return true;
    }

private:
    Vec3 c_;
    Frame frame_;  // n = axis
    float h_, r_;
};

class DistantLight : public Light {
public:
    DistantLight(const Vec3& towardLight, float halfAngle, Color irradiance)
        : frame_(towardLight), E_(irradiance) {
        cosMax_ = std::cos(halfAngle);
        delta_ = halfAngle < 1e-5f || 1 - cosMax_ < 1e-9f;
        if (!delta_) L_ = E_ / (kPi * (1 - cosMax_ * cosMax_));  // cone integral of cos is pi sin^2
    }
    bool isInfinite() const override { return true; }
    LightSample sample(const Vec3& ref, Vec2 u, float time) const override {
        LightSample ls;
        ls.distance = kInf;
        if (delta_) {
            ls.wi = frame_.n;
            ls.Li = E_;
            ls.pdf = 1;
            ls.delta = true;
            return ls;
        }
        ls.wi = frame_.toWorld(sampleUniformCone(u, cosMax_));
        ls.pdf = uniformConePdf(cosMax_);
        ls.Li = L_;
        return ls;
    }
    float pdf(const Vec3& ref, const Vec3& wi, float t, float time) const override {
        return !delta_ && dot(wi, frame_.n) >= cosMax_ ? uniformConePdf(cosMax_) : 0;
    }
    Color radiance(const Vec3& wi, float time) const override {
        return !delta_ && dot(wi, frame_.n) >= cosMax_ ? L_ : Color(0);
    }
    Color power(const SceneBounds& b) const override {
        return portals_ ? E_ * projectedPortalArea_ : E_ * (kPi * b.radius * b.radius);
    }
    void setPortals(std::shared_ptr<const PortalSet> portals) override {
        portals_ = std::move(portals);
        std::vector<float> weights;
        projectedPortalArea_ = 0;
        for (const Portal& p : portals_->portals()) {
            weights.push_back(p.area * std::max(0.0f, dot(-frame_.n, p.travel)));
            projectedPortalArea_ += weights.back();
        }
        byProjectedArea_ = Distribution1D(weights.data(), int(weights.size()));
    }
    PhotonEmission emit(Vec2 uPos, Vec2 uDir, const SceneBounds& b, float) const override {
        Vec3 dir = delta_ ? frame_.n : frame_.toWorld(sampleUniformCone(uDir, cosMax_));
        if (portals_) {
            // From a portal, picked by its area projected towards the sun: E cos A / pdf.
            PhotonEmission e;
            e.ray.d = -dir;
            e.power = Color(0.0f);
            e.fromPortal = true;
            float pdfArea;
            int i = portals_->samplePoint(byProjectedArea_, uPos, &e.ray.o, &pdfArea);
            float cosine = i < 0 ? 0 : dot(-dir, portals_->portals()[size_t(i)].travel);
            if (cosine > 0 && pdfArea > 0) e.power = E_ * (cosine / pdfArea);
            return e;
        }
        // Photons start on a disc facing the light just outside the scene's bounding sphere.
        Frame f(dir);
        Vec2 d = sampleConcentricDisk(uPos);
        PhotonEmission e;
        e.ray.o = b.center + dir * b.radius + (f.s * d.x + f.t * d.y) * b.radius;
        e.ray.d = -dir;
        e.power = E_ * (kPi * b.radius * b.radius);
        return e;
    }

private:
    Frame frame_;
    Color E_, L_;
    float cosMax_ = 1;
    bool delta_ = true;
    std::shared_ptr<const PortalSet> portals_;
    Distribution1D byProjectedArea_;
    float projectedPortalArea_ = 0;
};

class DomeLight : public Light {
public:
    DomeLight(const Mat4& toWorld, Color scale, std::shared_ptr<Image> image) : scale_(scale), image_(std::move(image)) {
        toWorld_ = toWorld;
        toWorld.inverse(toLocal_);
        if (image_) buildDistribution();
    }
    bool isInfinite() const override { return true; }
    // Its photons start on a disc facing their own direction: a place on that disc is a
    // different place in the scene for every direction, nothing a guide over uPos could learn.
    bool emitsFromFixedPositions() const override { return false; }
    bool isDome() const override { return true; }
    LightSample sample(const Vec3& ref, Vec2 u, float time) const override {
        LightSample ls;
        ls.distance = kInf;
        if (portals_ && portals_->guides(ref)) {
            if (portals_->sampleDirection(ref, u, &ls.wi, &ls.pdf)) ls.Li = radiance(ls.wi, time);
            else ls.pdf = 0;
            return ls;
        }
        if (!image_) {
            ls.wi = sampleUniformSphere(u);
            ls.pdf = uniformSpherePdf();
            ls.Li = scale_;
            return ls;
        }
        float pmfRow, pmfCol, uy, ux;
        int row = rows_.sample(u.y, &pmfRow, &uy);
        int col = cols_[row].sample(u.x, &pmfCol, &ux);
        float s = (col + ux) / image_->width(), t = (row + uy) / image_->height();
        float theta = t * kPi, phi = s * 2 * kPi - 0.5f * kPi;
        float sinTheta = std::sin(theta);
        Vec3 local(sinTheta * std::cos(phi), std::cos(theta), sinTheta * std::sin(phi));
        ls.wi = normalize(toWorld_.vector(local));
        float pdfUV = pmfRow * pmfCol * image_->width() * image_->height();
        ls.pdf = sinTheta > 1e-6f ? pdfUV / (2 * kPi * kPi * sinTheta) : 0;
        ls.Li = lookup(s, t);
        return ls;
    }
    float pdf(const Vec3& ref, const Vec3& wi, float t, float time) const override {
        if (portals_ && portals_->guides(ref)) return portals_->pdf(ref, wi);
        return directionPdf(wi);
    }
    float directionPdf(const Vec3& wi) const {
        if (!image_) return uniformSpherePdf();
        float s, t;
        toST(wi, s, t);
        int col = std::min(int(s * image_->width()), image_->width() - 1);
        int row = std::min(int(t * image_->height()), image_->height() - 1);
        float sinTheta = std::sin(t * kPi);
        if (sinTheta <= 1e-6f) return 0;
        return rows_.pmf(row) * cols_[row].pmf(col) * image_->width() * image_->height() / (2 * kPi * kPi * sinTheta);
    }
    Color radiance(const Vec3& wi, float time) const override {
        if (!image_) return scale_;
        float s, t;
        toST(wi, s, t);
        return lookup(s, t);
    }
    Color power(const SceneBounds& b) const override {
        // Through portals: the flux of a sky of the mean radiance through their area, pi L A.
        return portals_ ? average_ * (kPi * portals_->totalArea()) : average_ * (4 * kPi * kPi * b.radius * b.radius);
    }
    void setPortals(std::shared_ptr<const PortalSet> portals) override { portals_ = std::move(portals); }
    PhotonEmission emit(Vec2 uPos, Vec2 uDir, const SceneBounds& b, float) const override {
        if (portals_) {
            // From a portal picked by area, towards the interior, cosine-distributed about the
            // portal's direction: L(wi) cos / (cos / pi) / pdfArea.
            PhotonEmission e;
            e.power = Color(0.0f);
            e.fromPortal = true;
            float pdfArea;
            int i = portals_->samplePoint(portals_->byArea(), uPos, &e.ray.o, &pdfArea);
            if (i < 0 || !(pdfArea > 0)) return e;
            Vec3 travel = portals_->portals()[size_t(i)].travel;
            e.ray.d = Frame(travel).toWorld(sampleCosineHemisphere(uDir));
            e.powerPerRadiance = kPi / pdfArea;
            e.power = radiance(-e.ray.d, 0) * e.powerPerRadiance;
            return e;
        }
        LightSample ls = sample(b.center, uDir, 0);
        Frame f(ls.wi);
        Vec2 d = sampleConcentricDisk(uPos);
        PhotonEmission e;
        e.ray.o = b.center + ls.wi * b.radius + (f.s * d.x + f.t * d.y) * b.radius;
        e.ray.d = -ls.wi;
        e.power = ls.pdf > 0 ? ls.Li * (kPi * b.radius * b.radius / ls.pdf) : Color(0);
        return e;
    }

private:
    // Storm's lat-long convention (hdSt surfaceHelpers ProjectToLatLong): +Y up, +Z at s = 0.
    void toST(const Vec3& wi, float& s, float& t) const {
        Vec3 d = normalize(toLocal_.vector(wi));
        s = (std::atan2(d.z, d.x) + 0.5f * kPi) / (2 * kPi);
        if (s < 0) s += 1;
        if (s >= 1) s -= 1;
        t = std::acos(std::clamp(d.y, -1.0f, 1.0f)) / kPi;
    }
    Color lookup(float s, float t) const {
        float px[4];
        image_->lookup(s, 1 - t, kWrapRepeat, kWrapClamp, px);
        return scale_ * Color(px[0], px[1], px[2]);
    }
    void buildDistribution() {
        int w = image_->width(), h = image_->height();
        std::vector<float> rowWeights(h);
        double sum = 0;
        cols_.clear();
        for (int y = 0; y < h; ++y) {
            float sinTheta = std::sin((y + 0.5f) * kPi / h);
            std::vector<float> weights(w);
            double rowSum = 0;
            for (int x = 0; x < w; ++x) {
                float t[4];
                image_->texel(x, y, t);
                float lum = luminance(Color(t[0], t[1], t[2]));
                weights[x] = lum * sinTheta;
                rowSum += weights[x];
                sum += lum * sinTheta;
            }
            cols_.emplace_back(weights.data(), w);
            rowWeights[y] = float(rowSum);
        }
        rows_ = Distribution1D(rowWeights.data(), h);
        // Mean radiance over the sphere (solid-angle weighted) for the power estimate.
        double avg[3] = {0, 0, 0}, wsum = 0;
        for (int y = 0; y < h; ++y) {
            float sinTheta = std::sin((y + 0.5f) * kPi / h);
            for (int x = 0; x < w; ++x) {
                float t[4];
                image_->texel(x, y, t);
                for (int c = 0; c < 3; ++c) avg[c] += t[c] * sinTheta;
                wsum += sinTheta;
            }
        }
        average_ = scale_ * Color(float(avg[0] / wsum), float(avg[1] / wsum), float(avg[2] / wsum));
    }

    Mat4 toWorld_, toLocal_;
    std::shared_ptr<const PortalSet> portals_;
    Color scale_;
    Color average_{0.0f};
    std::shared_ptr<Image> image_;
    Distribution1D rows_;
    std::vector<Distribution1D> cols_;

public:
    void setConstantAverage() { average_ = scale_; }
};

bool finite(const LightDesc& d) {
    float v[] = {d.color.x, d.color.y, d.color.z, d.intensity, d.exposure, d.width, d.height, d.radius, d.length, d.angle};
    for (float x : v)
        if (!std::isfinite(x)) return false;
    for (const Mat4& m : d.motionTransforms)
        if (!m.isFinite()) return false;
    return d.transform.isFinite();
}

// The light of d's kind placed by `m`, of radiance L (before `normalize` divides it by the area);
// nullptr and a warning when it cannot emit.
std::unique_ptr<Light> placedLight(const LightDesc& d, const Mat4& m, Color L, std::string& warning) {
    auto scaled = [&](float area) -> bool {
        if (!(area > 0) || !std::isfinite(area)) {
            warning = "light " + d.name + ": zero area; ignored";
            return false;
        }
        if (d.normalize) L = L / area;
        if (!isFinite(L)) {
            warning = "light " + d.name + ": normalized radiance overflows a float (area " + std::to_string(area) +
                      "); ignored";
            return false;
        }
        return true;
    };
    if (d.kind == "rect") {
        Vec3 p0 = m.point(Vec3(-d.width / 2, -d.height / 2, 0));
        Vec3 e1 = m.vector(Vec3(d.width, 0, 0)), e2 = m.vector(Vec3(0, d.height, 0));
        if (!scaled(length(cross(e1, e2)))) return nullptr;
        return std::make_unique<RectLight>(p0, e1, e2, normalize(m.normal(Vec3(0, 0, -1))), L);
    }
    if (d.kind == "disk") {
        float r = d.radius * std::sqrt(length(m.vector(Vec3(1, 0, 0))) * length(m.vector(Vec3(0, 1, 0))));
        if (!scaled(kPi * r * r)) return nullptr;
        return std::make_unique<DiskLight>(m.point(Vec3(0.0f)), normalize(m.normal(Vec3(0, 0, -1))), r, L);
    }
    if (d.kind == "sphere") {
        float s = std::cbrt(std::fabs(float(m.det3())));
        float r = d.radius * s;
        if (!scaled(4 * kPi * r * r)) return nullptr;
        return std::make_unique<SphereLight>(m.point(Vec3(0.0f)), r, L);
    }
    if (d.kind == "cylinder") {
        Vec3 axis = m.vector(Vec3(d.length / 2, 0, 0));
        float r = d.radius * std::sqrt(length(m.vector(Vec3(0, 1, 0))) * length(m.vector(Vec3(0, 0, 1))));
        float h = length(axis);
        if (!scaled(2 * kPi * r * 2 * h)) return nullptr;
        return std::make_unique<CylinderLight>(m.point(Vec3(0.0f)), axis, h, r, L);
    }
    if (d.kind == "distant") {
        float halfAngle = std::clamp(d.angle, 0.0f, 180.0f) * 0.5f * kPi / 180.0f;
        // UsdLux: the intensity is the radiance of the light's disc (the schema's default of
        // 50000 at 0.53 degrees approximates the sun); `normalize` makes it the irradiance at
        // normal incidence instead, whatever the angular size. A delta light has only the latter.
        Color irradiance = L;
        float s = std::sin(std::min(halfAngle, 0.5f * kPi));
        if (!d.normalize && halfAngle >= 1e-5f) irradiance = L * (kPi * s * s);
        return std::make_unique<DistantLight>(normalize(m.vector(Vec3(0, 0, 1))), halfAngle, irradiance);
    }
    if (d.kind == "dome") {
        std::shared_ptr<Image> image;
        if (!d.textureFile.empty()) {
            std::string error;
            image = Image::load(d.textureFile, "auto", error);
            if (!image) warning = "light " + d.name + ": cannot read texture " + d.textureFile + " (" + error + "); using its color";
        }
        auto dome = std::make_unique<DomeLight>(m, L, image);
        if (!image) dome->setConstantAverage();
        return dome;
    }
    warning = "light " + d.name + ": unsupported light kind '" + d.kind + "'; ignored";
    return nullptr;
}

// The light of d's kind at each of its motion steps, moving between them (moving_light.h).
template <typename Kind>
std::unique_ptr<Light> movingLight(const LightDesc& d, Color L, std::string& warning) {
    std::vector<Kind> steps;
    for (const Mat4& m : d.motionTransforms) {
        std::unique_ptr<Light> step = placedLight(d, m, L, warning);
        if (!step) return nullptr;
        steps.push_back(static_cast<const Kind&>(*step));
    }
    return std::make_unique<MovingLight<Kind>>(std::move(steps));
}

}  // namespace

bool lightKindMoves(const std::string& kind) {
    return kind == "rect" || kind == "disk" || kind == "sphere" || kind == "cylinder";
}

std::unique_ptr<Light> createLight(const LightDesc& d, std::string& warning) {
    if (!finite(d)) {
        warning = "light " + d.name + ": NaN or Inf in its parameters or transform; ignored";
        return nullptr;
    }
    Color L = baseRadiance(d);
    if (!isFinite(L)) {
        warning = "light " + d.name + ": color x intensity x 2^exposure overflows a float; ignored";
        return nullptr;
    }
    if (!(maxComponent(L) > 0)) {
        warning = "light " + d.name + ": zero or negative intensity; ignored";
        return nullptr;
    }
    if (L.x < 0 || L.y < 0 || L.z < 0) warning = "light " + d.name + ": negative color components set to 0";
    L = vmax(L, Color(0.0f));
    std::unique_ptr<Light> light;
    if (d.motionTransforms.size() < 2 || !lightKindMoves(d.kind)) light = placedLight(d, d.transform, L, warning);
    else if (d.kind == "rect") light = movingLight<RectLight>(d, L, warning);
    else if (d.kind == "disk") light = movingLight<DiskLight>(d, L, warning);
    else if (d.kind == "sphere") light = movingLight<SphereLight>(d, L, warning);
    else light = movingLight<CylinderLight>(d, L, warning);
    if (!light) return nullptr;
    light->name = d.name;
    light->visibleToCamera = d.visibleToCamera;
    return light;
}

}  // namespace gi
