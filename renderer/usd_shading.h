// Shading rules both USD front ends follow (hdGi from Hydra's material networks and primvars, the
// gi loader from UsdShade/UsdGeom through gi._core), so that one stage renders the same in both.
// Each rule is UsdImaging's (OpenUSD 24.11, as Storm draws it) unless its comment says otherwise.
#pragma once
#include <string>
#include <vector>

#include "material.h"

namespace gi {

// A UsdPreviewSurface input (diffuseColor, emissiveColor, specularColor, metallic, roughness,
// opacity, normal) connected to a UsdUVTexture: the texture goes into the input's slot and the
// input's constant becomes the texture's `fallback` (authored, else the spec's (0, 0, 0, 1)) in the
// channel the connection reads. That constant is what the input reads when the file is missing or
// unreadable: Storm binds the texture node's fallback, and the input's own authored value is
// overridden by its connection. False (nothing changed) for an input name not listed.
bool connectTexture(MaterialDesc& material, const std::string& input, const TextureDesc& texture);

// The material of a gprim with no usable material bound: a UsdPreviewSurface with the spec's
// defaults (0.18 diffuse, specular through the 1.5 IOR's Fresnel at roughness 0.5) and its
// displayColor as diffuseColor when it has one. displayColor is the prim's own primvar, else the
// nearest ancestor's constant one (UsdImaging's primvar inheritance); its first value stands for
// the prim (per-point colours are not shaded).
MaterialDesc displayColorMaterial(const std::string& primPath, const Color* displayColor);

// The texture-coordinate primvar a mesh is read with: the first of the names its materials'
// UsdPrimvarReader_float2 nodes read (varname; the mesh's own material first, then its GeomSubsets')
// that the mesh has (without the "primvars:" prefix). No such primvar (or no reader): "", no
// texture coordinates, so textures read st (0, 0) everywhere, the reader's fallback. Storm reads
// only the named primvar; no st, st0 or UVMap guess is made.
std::string uvPrimvarOf(const std::vector<std::string>& readerVarnames, const std::vector<std::string>& meshPrimvars);

}  // namespace gi
