#include "preview_surface.h"

#include <algorithm>
#include <set>

#include "texture.h"
#include "usd_shading.h"

namespace gi {

namespace {

const char* const kValueTypeNames[] = {"float", "float2", "float3", "float4", "string", "asset"};

// The UsdPreviewSurface inputs a UsdUVTexture may drive, in the order their readers' varnames are
// listed (usd_shading.h's connectTexture puts each in its slot).
const char* const kTexturedInputs[] = {"diffuseColor", "emissiveColor", "specularColor", "metallic",
                                       "roughness",    "opacity",       "normal"};

std::string describe(const ShaderNode* node) {
    if (!node) return "not in the network";
    return node->id.empty() ? "no shader id" : node->id;
}

// Reads one material's network, warning once per message.
class Resolver {
public:
    Resolver(const std::string& materialPath, const ShaderNetwork& network, const ShadingWarning& warn)
        : materialPath_(materialPath), network_(network), warn_(warn) {}

    void warn(const std::string& message) {
        if (said_.insert(message).second) warn_(materialPath_, message);
    }

    const ShaderNode* node(const std::string& path) const {
        auto it = network_.nodes.find(path);
        return it == network_.nodes.end() ? nullptr : &it->second;
    }

    // Input `name` of `node` (at `path`) when it holds an authored constant of type T. A connected
    // input reads its connection, never its constant (UsdShade's rule); a constant of another type
    // is ignored with a warning, so the input keeps its default.
    template <class T>
    const T* constant(const ShaderNode& node, const std::string& path, const std::string& name) {
        if (node.connections.count(name)) return nullptr;
        auto it = node.parameters.find(name);
        if (it == node.parameters.end()) return nullptr;
        if (const T* value = std::get_if<T>(&it->second)) return value;
        warn("inputs:" + name + " of " + path + " has type " + kValueTypeNames[it->second.index()] + ", not " +
             kValueTypeNames[ShaderValue(T()).index()] + "; using the default");
        return nullptr;
    }
    void read(const ShaderNode& node, const std::string& path, const std::string& name, float& out) {
        if (const float* v = constant<float>(node, path, name)) out = *v;
    }
    void read(const ShaderNode& node, const std::string& path, const std::string& name, bool& out) {
        if (const float* v = constant<float>(node, path, name)) out = *v != 0;  // an int in the spec
    }
    void read(const ShaderNode& node, const std::string& path, const std::string& name, Color& out) {
        if (auto* v = constant<std::array<float, 3>>(node, path, name)) out = Color((*v)[0], (*v)[1], (*v)[2]);
    }
    void read(const ShaderNode& node, const std::string& path, const std::string& name, Vec2& out) {
        if (auto* v = constant<std::array<float, 2>>(node, path, name)) out = Vec2((*v)[0], (*v)[1]);
    }
    void read(const ShaderNode& node, const std::string& path, const std::string& name, float (&out)[4]) {
        if (auto* v = constant<std::array<float, 4>>(node, path, name)) std::copy(v->begin(), v->end(), out);
    }
    void read(const ShaderNode& node, const std::string& path, const std::string& name, std::string& out) {
        if (auto* v = constant<std::string>(node, path, name)) out = *v;
    }

    PreviewSurface surface(const ShaderNode& s, const std::string& path) {
        PreviewSurface result;
        MaterialDesc& d = result.material;
        d.name = materialPath_;
        read(s, path, "diffuseColor", d.diffuseColor);
        read(s, path, "emissiveColor", d.emissiveColor);
        read(s, path, "useSpecularWorkflow", d.useSpecularWorkflow);
        read(s, path, "specularColor", d.specularColor);
        read(s, path, "metallic", d.metallic);
        read(s, path, "roughness", d.roughness);
        read(s, path, "clearcoat", d.clearcoat);
        read(s, path, "clearcoatRoughness", d.clearcoatRoughness);
        read(s, path, "opacity", d.opacity);
        read(s, path, "opacityMode", d.opacityMode);
        read(s, path, "opacityThreshold", d.opacityThreshold);
        read(s, path, "ior", d.ior);
        for (const char* input : kTexturedInputs) {
            auto c = s.connections.find(input);
            TextureDesc texture;
            if (c != s.connections.end() && readTexture(input, c->second, &texture, &result))
                connectTexture(d, input, texture);
        }
        for (const auto& [input, c] : s.connections) {
            if (std::find(std::begin(kTexturedInputs), std::end(kTexturedInputs), input) != std::end(kTexturedInputs))
                continue;
            if (input == "displacement") warn("displacement is not supported; ignored");
            // occlusion is ambient occlusion baked for rasterisers; a path tracer finds its own.
            else if (input != "occlusion") unsupported("inputs:" + input + " of " + path, c, "using the default");
        }
        return result;
    }

private:
    void unsupported(const std::string& what, const ShaderConnection& c, const std::string& consequence) {
        warn(what + " is driven by " + c.node + " (" + describe(node(c.node)) + "), which is not supported there; " +
             consequence);
    }

    // The UsdUVTexture driving surface input `input` through `c`, read into `texture`; false (after a
    // warning) when another kind of node drives it.
    bool readTexture(const std::string& input, const ShaderConnection& c, TextureDesc* texture, PreviewSurface* out) {
        const ShaderNode* t = node(c.node);
        if (!t || t->id != "UsdUVTexture") {
            unsupported("inputs:" + input, c, "using the default");
            return false;
        }
        const std::string& path = c.node;
        if (const ShaderAsset* file = constant<ShaderAsset>(*t, path, "file"); file && !file->authored.empty()) {
            bool listed = std::any_of(out->textureFiles.begin(), out->textureFiles.end(),
                                      [&](const ShaderAsset& a) { return a.authored == file->authored; });
            if (!listed) out->textureFiles.push_back(*file);
            texture->file = file->resolved;
            // A UDIM pattern no resolver resolves: UsdImaging's scene index hands it over as authored
            // (OpenUSD 24.11), which names its tiles only when absolute (the renderer finds them).
            if (texture->file.empty() && isUdimPath(file->authored) && file->authored.front() == '/')
                texture->file = file->authored;
            if (texture->file.empty())
                warn("texture file '" + file->authored + "' (read by " + path + ") was not found" +
                     (isUdimPath(file->authored) ? " (no tile of this UDIM pattern was found; Hydra's scene "
                                                   "index in OpenUSD 24.11 finds them by an absolute path only)"
                                                 : "") +
                     "; using its fallback");
        } else {
            warn("texture " + path + " has no file; using its fallback");
        }
        read(*t, path, "wrapS", texture->wrapS);
        read(*t, path, "wrapT", texture->wrapT);
        for (std::string* wrap : {&texture->wrapS, &texture->wrapT}) {
            int mode;
            if (!parseWrapMode(*wrap, &mode))
                warn(std::string(wrap == &texture->wrapS ? "wrapS" : "wrapT") + " '" + *wrap + "' of " + path +
                     " is not black, clamp, mirror, repeat or useMetadata; using repeat");
        }
        read(*t, path, "scale", texture->scale);
        read(*t, path, "bias", texture->bias);
        read(*t, path, "fallback", texture->fallback);
        read(*t, path, "sourceColorSpace", texture->sourceColorSpace);
        // Outputs r, g, b and a read one channel; rgb (and any other name) the colour.
        const std::string& output = c.output;
        texture->channel = output == "r" || output == "g" || output == "b" || output == "a" ? output : "rgb";
        std::string varname = readSt(*t, path, texture);
        auto& names = out->readerVarnames;
        if (!varname.empty() && std::find(names.begin(), names.end(), varname) == names.end()) names.push_back(varname);
        return true;
    }

    // The UsdTransform2d (optional) and UsdPrimvarReader_float2 feeding texture `t`'s st: fills the
    // transform into `texture` and returns the reader's varname ("" without a reader: the texture
    // reads st (0, 0), the reader's fallback).
    std::string readSt(const ShaderNode& t, const std::string& path, TextureDesc* texture) {
        auto c = t.connections.find("st");
        if (c == t.connections.end()) return "";
        const ShaderNode* n = node(c->second.node);
        std::string what = "inputs:st of " + path;
        ShaderConnection from = c->second;
        if (n && n->id == "UsdTransform2d") {
            read(*n, from.node, "rotation", texture->stRotation);
            read(*n, from.node, "scale", texture->stScale);
            read(*n, from.node, "translation", texture->stTranslation);
            auto in = n->connections.find("in");
            if (in == n->connections.end()) return "";
            what = "inputs:in of " + from.node;
            from = in->second;
            n = node(from.node);
        }
        // Storm reads any UsdPrimvarReader's varname here (float2 is the one that makes sense).
        if (!n || n->id.rfind("UsdPrimvarReader", 0) != 0) {
            unsupported(what, from, "it reads st (0, 0)");
            return "";
        }
        std::string varname;
        read(*n, from.node, "varname", varname);
        return varname;
    }

    const std::string& materialPath_;
    const ShaderNetwork& network_;
    const ShadingWarning& warn_;
    std::set<std::string> said_;
};

}  // namespace

std::optional<PreviewSurface> resolvePreviewSurface(const std::string& materialPath, const ShaderNetwork& network,
                                                    const std::string& surface, const ShadingWarning& warn) {
    Resolver resolver(materialPath, network, warn);
    const ShaderNode* s = resolver.node(surface);
    if (!s || s->id != "UsdPreviewSurface") {
        resolver.warn(surface.empty() ? "nothing drives its surface output; using the prim's displayColor"
                                      : "its surface output is driven by " + surface + " (" + describe(s) +
                                            "), not a UsdPreviewSurface; using the prim's displayColor");
        return std::nullopt;
    }
    return resolver.surface(*s, surface);
}

}  // namespace gi
