#include "render_vars.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <regex>

namespace gi {

namespace {

// Hydra's and USD's usual names, plus the spellings common in render settings (Ci, N, Z).
const std::map<std::string, RenderOutput>& sources() {
    static const std::map<std::string, RenderOutput> m = {
        {"color", RenderOutput::Color},        {"Ci", RenderOutput::Color},
        {"C", RenderOutput::Color},            {"depth", RenderOutput::Depth},
        {"Z", RenderOutput::Depth},            {"z", RenderOutput::Depth},
        {"normal", RenderOutput::Normal},      {"N", RenderOutput::Normal},
        {"albedo", RenderOutput::Albedo},      {"diffuseColor", RenderOutput::Albedo},
        {"primId", RenderOutput::PrimId},      {"instanceId", RenderOutput::InstanceId},
    };
    return m;
}

struct Storage {
    std::vector<std::string> suffixes;
    bool half;
};

const std::map<std::string, Storage>& dataTypes() {
    static const std::vector<std::string> color{"R", "G", "B"}, vector{"X", "Y", "Z"}, scalar{""};
    static const std::map<std::string, Storage> m = {
        {"color3f", {color, false}},   {"color3h", {color, true}},   {"float3", {color, false}},
        {"half3", {color, true}},      {"normal3f", {vector, false}}, {"normal3h", {vector, true}},
        {"vector3f", {vector, false}}, {"vector3h", {vector, true}}, {"point3f", {vector, false}},
        {"point3h", {vector, true}},   {"float", {scalar, false}},   {"half", {scalar, true}},
        {"int", {scalar, false}},      {"uint", {scalar, false}},
    };
    return m;
}

template <typename Map>
std::string keys(const Map& m) {
    std::vector<std::string> names;
    for (const auto& entry : m) names.push_back(entry.first);
    std::sort(names.begin(), names.end());
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

// $F, $F<width> or a run of '#'.
const std::regex& frameToken() {
    static const std::regex re(R"(\$F(\d*)|(#+))");
    return re;
}

}  // namespace

const char* outputName(RenderOutput output) {
    switch (output) {
        case RenderOutput::Color: return "color";
        case RenderOutput::Depth: return "depth";
        case RenderOutput::Normal: return "normal";
        case RenderOutput::Albedo: return "albedo";
        case RenderOutput::PrimId: return "prim_id";
        case RenderOutput::InstanceId: return "instance_id";
    }
    return "";
}

std::optional<RenderOutput> outputNamed(const std::string& name) {
    for (RenderOutput o : {RenderOutput::Color, RenderOutput::Depth, RenderOutput::Normal, RenderOutput::Albedo,
                           RenderOutput::PrimId, RenderOutput::InstanceId})
        if (name == outputName(o)) return o;
    return std::nullopt;
}

int outputComponents(RenderOutput output) {
    return output == RenderOutput::Color || output == RenderOutput::Normal || output == RenderOutput::Albedo ? 3 : 1;
}

std::optional<RenderVarLayout> renderVarLayout(const std::string& sourceName, const std::string& dataType,
                                               std::string* problem) {
    auto source = sources().find(sourceName);
    if (source == sources().end()) {
        *problem = "sourceName '" + sourceName + "' is not an output of this renderer (it has: " + keys(sources()) + ")";
        return std::nullopt;
    }
    auto storage = dataTypes().find(dataType);
    if (storage == dataTypes().end()) {
        *problem = "dataType '" + dataType + "' is not one this renderer writes (" + keys(dataTypes()) + ")";
        return std::nullopt;
    }
    int components = outputComponents(source->second);
    if (int(storage->second.suffixes.size()) != components) {
        *problem = "dataType '" + dataType + "' has " + std::to_string(storage->second.suffixes.size()) +
                   " channels but '" + sourceName + "' has " + std::to_string(components);
        return std::nullopt;
    }
    return RenderVarLayout{source->second, storage->second.suffixes, storage->second.half};
}

std::string renderVarLayer(const std::string& varName, RenderOutput output, bool beautyTaken) {
    return output == RenderOutput::Color && !beautyTaken ? std::string() : varName;
}

std::string channelName(const std::string& layer, const std::string& suffix) {
    if (layer.empty()) return suffix;
    return suffix.empty() ? layer : layer + "." + suffix;
}

uint32_t frameSeed(uint32_t seed, double frame) {
    if (!std::isfinite(frame)) return seed;
    // Whole frames wrap modulo 2^32 (negative frames too); beyond 2^62 a double has no fraction.
    double const whole = std::round(std::clamp(frame, -0x1p62, 0x1p62));
    return seed + uint32_t(uint64_t(int64_t(whole)));
}

std::string substituteFrame(const std::string& path, int frame) {
    std::string out;
    auto begin = std::sregex_iterator(path.begin(), path.end(), frameToken());
    size_t last = 0;
    for (auto it = begin; it != std::sregex_iterator(); ++it) {
        const std::smatch& m = *it;
        out += path.substr(last, size_t(m.position()) - last);
        int width = m[2].matched ? int(m[2].length()) : (m[1].length() ? std::stoi(m[1].str()) : 0);
        char buffer[64];
        std::snprintf(buffer, sizeof buffer, "%0*d", width, frame);
        out += width ? buffer : std::to_string(frame);
        last = size_t(m.position() + m.length());
    }
    return out + path.substr(last);
}

bool hasFrameToken(const std::string& path) { return std::regex_search(path, frameToken()); }

}  // namespace gi
