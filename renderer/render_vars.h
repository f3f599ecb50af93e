// UsdRender products and vars, the rules both hosts follow (`gi render`'s products.py and hdGi's
// products): which renderer output a var's sourceName names, how its dataType stores it (channel
// suffixes, half or float), the var's layer name in the EXR, and a productName's frame tokens.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace gi {

// What the renderer computes per pixel (Film's outputs).
enum class RenderOutput { Color, Depth, Normal, Albedo, PrimId, InstanceId };

const char* outputName(RenderOutput output);  // "color", "depth", ..., "prim_id", "instance_id"
std::optional<RenderOutput> outputNamed(const std::string& name);
int outputComponents(RenderOutput output);

struct RenderVarLayout {
    RenderOutput output;
    std::vector<std::string> suffixes;  // e.g. {"R","G","B"}, {"X","Y","Z"} or {""}
    bool half = false;                  // stored as 16-bit half floats
};

// The layout of a var with this sourceName and dataType, or nullopt with *problem set (a
// sentence for a warning naming the var: the var is then skipped). Ints are stored as 32-bit
// float channels: EXR has no signed integer channel, and ids (-1 for none) are exact below 2^24.
std::optional<RenderVarLayout> renderVarLayout(const std::string& sourceName, const std::string& dataType,
                                               std::string* problem);

// The var's channels are named layer.suffix; the first colour var of a product is the beauty,
// written as plain R, G, B (what an EXR viewer shows).
std::string renderVarLayer(const std::string& varName, RenderOutput output, bool beautyTaken);
std::string channelName(const std::string& layer, const std::string& suffix);

// `path` with its frame tokens replaced by `frame`: `####` and `$F4` zero-padded to their width,
// `$F` not padded.
std::string substituteFrame(const std::string& path, int frame);
bool hasFrameToken(const std::string& path);

// The seed frame `frame` renders with, in both hosts: seed + frame (mod 2^32), the frame rounded to
// a whole number as file names are. The sampler hashes the seed, so neighbouring frames' noise is
// decorrelated, and a frame renders alone as in a sequence, a farm chunk or usdrecord's --frames.
// A frame that is no number (USD's default time) keeps the seed.
uint32_t frameSeed(uint32_t seed, double frame);

}  // namespace gi
