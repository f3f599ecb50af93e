// gi._core.read_obj / read_gltf: OBJ (tinyobjloader) and glTF 2.0 (tinygltf) sources parsed into
// plain dicts of numpy arrays, for gi.importer to author as USD. Nothing here knows about USD.
//
// OBJ: one mesh per (group, material) pair, in file order; faces are kept as authored (polygons
// are not triangulated); points, normals and uvs are compacted to what each mesh uses, in the
// order of first use, so the output is a pure function of the file. Normals that are missing,
// zero-length or not finite are replaced by the face's geometric normal (and counted).
// glTF: meshes with their primitives (triangles; strips and fans are converted), the node tree with
// each node's local transform, materials (metallic-roughness) and images (a file, or the bytes of
// an embedded one).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <tiny_gltf.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace nb = nanobind;
using namespace nb::literals;

namespace {

template <typename T>
nb::ndarray<nb::numpy, T> array(std::vector<T> v, size_t columns) {
    auto* heap = new std::vector<T>(std::move(v));
    nb::capsule owner(heap, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
    size_t shape[2] = {columns ? heap->size() / columns : heap->size(), columns};
    return nb::ndarray<nb::numpy, T>(heap->data(), columns ? 2 : 1, shape, owner);
}

nb::list floats(const float* v, int n) {
    nb::list l;
    for (int i = 0; i < n; ++i) l.append(double(v[i]));
    return l;
}

struct V3 {
    double x, y, z;
};
V3 sub(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double length(V3 a) { return std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z); }

// A normal a renderer can use: finite and not (nearly) zero.
bool usable(double x, double y, double z) {
    double l2 = x * x + y * y + z * z;
    return std::isfinite(l2) && l2 > 1e-20;
}

// Compacts indices into a source array to the entries one mesh uses, in the order of first use.
class Compactor {
public:
    int map(int source) {
        auto [it, added] = remap_.try_emplace(source, int(order_.size()));
        if (added) order_.push_back(source);
        return it->second;
    }
    const std::vector<int>& order() const { return order_; }

private:
    std::unordered_map<int, int> remap_;
    std::vector<int> order_;
};

// ---- OBJ -------------------------------------------------------------------------------------

nb::dict objTexture(const std::string& name, const tinyobj::texture_option_t& opt) {
    nb::dict t;
    t["file"] = name;
    t["scale"] = floats(opt.scale, 2);
    t["offset"] = floats(opt.origin_offset, 2);
    t["bump_multiplier"] = double(opt.bump_multiplier);
    return t;
}

nb::dict objMaterial(const tinyobj::material_t& m) {
    nb::dict d;
    d["name"] = m.name;
    d["Ka"] = floats(m.ambient, 3);
    d["Kd"] = floats(m.diffuse, 3);
    d["Ks"] = floats(m.specular, 3);
    d["Ke"] = floats(m.emission, 3);
    d["Tf"] = floats(m.transmittance, 3);
    d["Ns"] = double(m.shininess);
    d["Ni"] = double(m.ior);
    d["d"] = double(m.dissolve);
    d["illum"] = m.illum;
    d["Pr"] = double(m.roughness);
    d["Pm"] = double(m.metallic);
    nb::dict maps;
    auto add = [&](const char* key, const std::string& name, const tinyobj::texture_option_t& opt) {
        if (!name.empty()) maps[key] = objTexture(name, opt);
    };
    add("map_Kd", m.diffuse_texname, m.diffuse_texopt);
    add("map_Ka", m.ambient_texname, m.ambient_texopt);
    add("map_Ks", m.specular_texname, m.specular_texopt);
    add("map_Ns", m.specular_highlight_texname, m.specular_highlight_texopt);
    add("bump", m.bump_texname, m.bump_texopt);
    add("disp", m.displacement_texname, m.displacement_texopt);
    add("map_d", m.alpha_texname, m.alpha_texopt);
    add("map_Ke", m.emissive_texname, m.emissive_texopt);
    add("map_Pr", m.roughness_texname, m.roughness_texopt);
    add("map_Pm", m.metallic_texname, m.metallic_texopt);
    add("norm", m.normal_texname, m.normal_texopt);
    d["maps"] = maps;
    return d;
}

nb::dict readObj(const std::string& path) {
    if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(path + ": no such file");
    tinyobj::ObjReaderConfig config;
    config.triangulate = false;
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    bool ok;
    {
        nb::gil_scoped_release release;
        ok = reader.ParseFromFile(path, config);
    }
    if (!ok || !reader.Valid()) {
        std::string error = reader.Error();
        while (!error.empty() && (error.back() == '\n' || error.back() == '\r')) error.pop_back();
        throw std::runtime_error(path + ": not a readable OBJ file (" + (error.empty() ? "parse error" : error) + ")");
    }
    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    const auto& shapes = reader.GetShapes();
    const size_t nv = attrib.vertices.size() / 3, nn = attrib.normals.size() / 3, nt = attrib.texcoords.size() / 2;

    nb::list meshes;
    int64_t repaired = 0, degenerate = 0, facesTotal = 0;
    for (const tinyobj::shape_t& shape : shapes) {
        const tinyobj::mesh_t& mesh = shape.mesh;
        const size_t faces = mesh.num_face_vertices.size();
        if (faces == 0) continue;
        // Face offsets into mesh.indices, and the materials in order of first use.
        std::vector<size_t> offset(faces + 1, 0);
        for (size_t f = 0; f < faces; ++f) offset[f + 1] = offset[f] + mesh.num_face_vertices[f];
        std::vector<int> materials;
        for (size_t f = 0; f < faces; ++f) {
            int m = f < mesh.material_ids.size() ? mesh.material_ids[f] : -1;
            if (std::find(materials.begin(), materials.end(), m) == materials.end()) materials.push_back(m);
        }
        for (int material : materials) {
            Compactor points, normals, uvs;
            std::vector<int> counts, pointIndices, normalIndices, uvIndices;
            std::vector<float> extraNormals;  // replacements, appended after the source normals
            bool allUvs = true;
            for (size_t f = 0; f < faces; ++f) {
                int m = f < mesh.material_ids.size() ? mesh.material_ids[f] : -1;
                if (m != material) continue;
                ++facesTotal;
                const int n = mesh.num_face_vertices[f];
                counts.push_back(n);
                // Newell's normal of the polygon: the geometric normal, also for non-planar faces.
                V3 newell{0, 0, 0};
                bool facePointsOk = true;
                for (int k = 0; k < n; ++k) {
                    int a = mesh.indices[offset[f] + k].vertex_index;
                    int b = mesh.indices[offset[f] + (k + 1) % n].vertex_index;
                    if (a < 0 || b < 0 || size_t(a) >= nv || size_t(b) >= nv) {
                        facePointsOk = false;
                        break;
                    }
                    V3 pa{attrib.vertices[3 * a], attrib.vertices[3 * a + 1], attrib.vertices[3 * a + 2]};
                    V3 pb{attrib.vertices[3 * b], attrib.vertices[3 * b + 1], attrib.vertices[3 * b + 2]};
                    newell.x += (pa.y - pb.y) * (pa.z + pb.z);
                    newell.y += (pa.z - pb.z) * (pa.x + pb.x);
                    newell.z += (pa.x - pb.x) * (pa.y + pb.y);
                }
                if (!facePointsOk) {
                    throw std::runtime_error(path + ": face " + std::to_string(f + 1) + " of group '" + shape.name +
                                             "' names a vertex that does not exist");
                }
                double len = length(newell);
                bool flat = usable(newell.x, newell.y, newell.z) && len > 0;
                if (!flat) ++degenerate;
                int faceNormal = -1;  // index of this face's replacement normal, once added
                for (int k = 0; k < n; ++k) {
                    const tinyobj::index_t& idx = mesh.indices[offset[f] + k];
                    pointIndices.push_back(points.map(idx.vertex_index));
                    int ni = idx.normal_index;
                    bool good = ni >= 0 && size_t(ni) < nn &&
                                usable(attrib.normals[3 * ni], attrib.normals[3 * ni + 1], attrib.normals[3 * ni + 2]);
                    if (good) {
                        normalIndices.push_back(normals.map(ni));
                    } else {
                        if (nn > 0) ++repaired;  // the source has normals, and this one is unusable
                        if (faceNormal < 0) {
                            // A degenerate face is never hit; any unit vector will do.
                            V3 g = flat ? V3{newell.x / len, newell.y / len, newell.z / len} : V3{0, 1, 0};
                            faceNormal = int(nn + extraNormals.size() / 3);
                            extraNormals.insert(extraNormals.end(), {float(g.x), float(g.y), float(g.z)});
                        }
                        normalIndices.push_back(normals.map(faceNormal));
                    }
                    int ti = idx.texcoord_index;
                    if (ti >= 0 && size_t(ti) < nt)
                        uvIndices.push_back(uvs.map(ti));
                    else
                        allUvs = false;
                }
            }
            std::vector<float> p, nrm, uv;
            p.reserve(points.order().size() * 3);
            for (int i : points.order())
                p.insert(p.end(), {attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]});
            for (int i : normals.order()) {
                const float* src = size_t(i) < nn ? &attrib.normals[3 * i] : &extraNormals[3 * (i - nn)];
                nrm.insert(nrm.end(), {src[0], src[1], src[2]});
            }
            if (allUvs)
                for (int i : uvs.order()) uv.insert(uv.end(), {attrib.texcoords[2 * i], attrib.texcoords[2 * i + 1]});
            else
                uvIndices.clear();
            nb::dict d;
            d["name"] = shape.name;
            d["material"] = material;
            d["points"] = array(std::move(p), 3);
            d["face_vertex_counts"] = array(std::move(counts), 0);
            d["face_vertex_indices"] = array(std::move(pointIndices), 0);
            d["normals"] = array(std::move(nrm), 3);
            d["normal_indices"] = array(std::move(normalIndices), 0);
            d["source_has_normals"] = nn > 0;
            d["uvs"] = array(std::move(uv), 2);
            d["uv_indices"] = array(std::move(uvIndices), 0);
            meshes.append(d);
        }
    }
    nb::list materials;
    for (const auto& m : reader.GetMaterials()) materials.append(objMaterial(m));
    nb::dict result;
    result["meshes"] = meshes;
    result["materials"] = materials;
    result["faces"] = facesTotal;
    result["repaired_normals"] = repaired;
    result["degenerate_faces"] = degenerate;
    result["warnings"] = reader.Warning();
    return result;
}

// ---- glTF ------------------------------------------------------------------------------------

// Keeps an embedded image's bytes (and nothing decoded): the importer writes them out as files.
bool keepImageBytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int, const unsigned char* bytes,
                    int size, void*) {
    image->image.assign(bytes, bytes + size);
    image->width = image->height = -1;
    return true;
}

// An accessor's elements as `components` doubles each (normalized integers mapped to [0,1]/[-1,1]).
std::vector<double> readAccessor(const tinygltf::Model& model, int index, int components, const std::string& what) {
    if (index < 0 || size_t(index) >= model.accessors.size()) throw std::runtime_error(what + ": no such accessor");
    const tinygltf::Accessor& a = model.accessors[index];
    int have = tinygltf::GetNumComponentsInType(a.type);
    int bytes = tinygltf::GetComponentSizeInBytes(a.componentType);
    if (have != components || bytes <= 0) throw std::runtime_error(what + ": unexpected accessor type");
    std::vector<double> out(a.count * components, 0.0);
    if (a.bufferView < 0) return out;  // all zeros (sparse accessors are not supported)
    const tinygltf::BufferView& view = model.bufferViews.at(a.bufferView);
    const tinygltf::Buffer& buffer = model.buffers.at(view.buffer);
    size_t stride = a.ByteStride(view);
    if (stride == 0 || stride == size_t(-1)) throw std::runtime_error(what + ": bad byte stride");
    size_t start = view.byteOffset + a.byteOffset;
    if (a.count > 0 && start + stride * (a.count - 1) + size_t(components) * bytes > buffer.data.size())
        throw std::runtime_error(what + ": accessor runs past the end of its buffer");
    for (size_t i = 0; i < a.count; ++i) {
        const unsigned char* e = buffer.data.data() + start + i * stride;
        for (int c = 0; c < components; ++c) {
            const unsigned char* p = e + c * bytes;
            double v = 0;
            switch (a.componentType) {
                case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p, 4); v = f; break; }
                case TINYGLTF_COMPONENT_TYPE_DOUBLE: { std::memcpy(&v, p, 8); break; }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = *p; if (a.normalized) v /= 255.0; break;
                case TINYGLTF_COMPONENT_TYPE_BYTE: v = int8_t(*p); if (a.normalized) v = std::max(v / 127.0, -1.0); break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t s; std::memcpy(&s, p, 2); v = s; if (a.normalized) v /= 65535.0; break; }
                case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t s; std::memcpy(&s, p, 2); v = s; if (a.normalized) v = std::max(v / 32767.0, -1.0); break; }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t s; std::memcpy(&s, p, 4); v = s; break; }
                case TINYGLTF_COMPONENT_TYPE_INT: { int32_t s; std::memcpy(&s, p, 4); v = s; break; }
                default: throw std::runtime_error(what + ": unknown component type");
            }
            out[i * components + c] = v;
        }
    }
    return out;
}

std::vector<float> toFloat(const std::vector<double>& v) { return {v.begin(), v.end()}; }

nb::dict gltfPrimitive(const tinygltf::Model& model, const tinygltf::Primitive& prim, const std::string& what,
                       int64_t& repaired) {
    auto attribute = [&](const char* name) {
        auto it = prim.attributes.find(name);
        return it == prim.attributes.end() ? -1 : it->second;
    };
    int pos = attribute("POSITION");
    if (pos < 0) throw std::runtime_error(what + " has no POSITION attribute");
    std::vector<double> p = readAccessor(model, pos, 3, what + " POSITION");
    const size_t n = p.size() / 3;
    std::vector<uint32_t> order;
    if (prim.indices >= 0) {
        for (double i : readAccessor(model, prim.indices, 1, what + " indices")) order.push_back(uint32_t(i));
    } else {
        for (size_t i = 0; i < n; ++i) order.push_back(uint32_t(i));
    }
    for (uint32_t i : order)
        if (i >= n) throw std::runtime_error(what + ": index " + std::to_string(i) + " is past its " + std::to_string(n) + " vertices");
    std::vector<int> tri;
    if (prim.mode == TINYGLTF_MODE_TRIANGLES || prim.mode == -1) {
        tri.assign(order.begin(), order.end() - order.size() % 3);
    } else if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (size_t i = 2; i < order.size(); ++i) {
            bool odd = i % 2;
            tri.insert(tri.end(), {int(order[i - 2 + odd]), int(order[i - 1 - odd]), int(order[i])});
        }
    } else if (prim.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
        for (size_t i = 2; i < order.size(); ++i) tri.insert(tri.end(), {int(order[0]), int(order[i - 1]), int(order[i])});
    } else {
        return nb::dict();  // points and lines: not surfaces
    }
    std::vector<double> nrm;
    if (int a = attribute("NORMAL"); a >= 0) nrm = readAccessor(model, a, 3, what + " NORMAL");
    std::vector<double> uv;
    if (int a = attribute("TEXCOORD_0"); a >= 0) {
        uv = readAccessor(model, a, 2, what + " TEXCOORD_0");
        for (size_t i = 1; i < uv.size(); i += 2) uv[i] = 1.0 - uv[i];  // glTF's v runs down, USD's t up
    }
    // Vertex normals, with unusable ones replaced by the area-weighted normal of the triangles
    // around the vertex (a glTF mesh without normals gets them all this way).
    bool sourceNormals = !nrm.empty();
    std::vector<char> bad(n, 0);
    size_t badCount = 0;
    if (nrm.empty()) nrm.assign(n * 3, 0.0);
    for (size_t i = 0; i < n; ++i)
        if (!sourceNormals || !usable(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2])) bad[i] = 1, ++badCount;
    if (badCount) {
        std::vector<double> acc(n * 3, 0.0);
        for (size_t t = 0; t + 2 < tri.size(); t += 3) {
            V3 a{p[3 * tri[t]], p[3 * tri[t] + 1], p[3 * tri[t] + 2]};
            V3 b{p[3 * tri[t + 1]], p[3 * tri[t + 1] + 1], p[3 * tri[t + 1] + 2]};
            V3 c{p[3 * tri[t + 2]], p[3 * tri[t + 2] + 1], p[3 * tri[t + 2] + 2]};
            V3 g = cross(sub(b, a), sub(c, a));
            for (int k = 0; k < 3; ++k) {
                acc[3 * tri[t + k]] += g.x, acc[3 * tri[t + k] + 1] += g.y, acc[3 * tri[t + k] + 2] += g.z;
            }
        }
        for (size_t i = 0; i < n; ++i) {
            if (!bad[i]) continue;
            V3 g{acc[3 * i], acc[3 * i + 1], acc[3 * i + 2]};
            double l = length(g);
            if (!usable(g.x, g.y, g.z) || l == 0) g = {0, 1, 0}, l = 1;
            nrm[3 * i] = g.x / l, nrm[3 * i + 1] = g.y / l, nrm[3 * i + 2] = g.z / l;
        }
        if (sourceNormals) repaired += int64_t(badCount);
    }
    nb::dict d;
    d["points"] = array(toFloat(p), 3);
    d["face_vertex_indices"] = array(std::move(tri), 0);
    d["normals"] = array(toFloat(nrm), 3);
    d["source_has_normals"] = sourceNormals;
    d["uvs"] = array(toFloat(uv), 2);
    d["material"] = prim.material;
    return d;
}

nb::dict textureRef(const tinygltf::Model& model, int texture, int texCoord) {
    nb::dict t;
    if (texture < 0 || size_t(texture) >= model.textures.size()) return t;
    const tinygltf::Texture& tex = model.textures[texture];
    t["image"] = tex.source;
    t["texcoord"] = texCoord;
    int wrapS = 10497, wrapT = 10497;
    if (tex.sampler >= 0 && size_t(tex.sampler) < model.samplers.size())
        wrapS = model.samplers[tex.sampler].wrapS, wrapT = model.samplers[tex.sampler].wrapT;
    t["wrap_s"] = wrapS;
    t["wrap_t"] = wrapT;
    return t;
}

nb::list doubles(const std::vector<double>& v) {
    nb::list l;
    for (double x : v) l.append(x);
    return l;
}

nb::dict readGltf(const std::string& path) {
    if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(path + ": no such file");
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(keepImageBytes, nullptr);
    std::string error, warning;
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    bool ok;
    {
        nb::gil_scoped_release release;
        ok = ext == ".glb" ? loader.LoadBinaryFromFile(&model, &error, &warning, path)
                           : loader.LoadASCIIFromFile(&model, &error, &warning, path);
    }
    if (!ok) {
        while (!error.empty() && (error.back() == '\n' || error.back() == '\r')) error.pop_back();
        throw std::runtime_error(path + ": not a readable glTF file (" + (error.empty() ? "parse error" : error) + ")");
    }
    int64_t repaired = 0;
    nb::list meshes;
    for (size_t m = 0; m < model.meshes.size(); ++m) {
        nb::list prims;
        for (size_t k = 0; k < model.meshes[m].primitives.size(); ++k) {
            std::string what = path + ": mesh " + std::to_string(m) + " ('" + model.meshes[m].name + "') primitive " + std::to_string(k);
            prims.append(gltfPrimitive(model, model.meshes[m].primitives[k], what, repaired));
        }
        nb::dict d;
        d["name"] = model.meshes[m].name;
        d["primitives"] = prims;
        meshes.append(d);
    }
    nb::list nodes;
    for (const tinygltf::Node& node : model.nodes) {
        nb::dict d;
        d["name"] = node.name;
        d["mesh"] = node.mesh;
        d["children"] = node.children;
        d["matrix"] = doubles(node.matrix);
        d["translation"] = doubles(node.translation);
        d["rotation"] = doubles(node.rotation);
        d["scale"] = doubles(node.scale);
        nodes.append(d);
    }
    nb::list materials;
    for (const tinygltf::Material& mat : model.materials) {
        const auto& pbr = mat.pbrMetallicRoughness;
        nb::dict d;
        d["name"] = mat.name;
        d["base_color"] = doubles(pbr.baseColorFactor);
        d["base_color_texture"] = textureRef(model, pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord);
        d["metallic"] = pbr.metallicFactor;
        d["roughness"] = pbr.roughnessFactor;
        d["metallic_roughness_texture"] =
            textureRef(model, pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord);
        d["normal_texture"] = textureRef(model, mat.normalTexture.index, mat.normalTexture.texCoord);
        d["normal_scale"] = mat.normalTexture.scale;
        d["occlusion_texture"] = textureRef(model, mat.occlusionTexture.index, mat.occlusionTexture.texCoord);
        d["emissive"] = doubles(mat.emissiveFactor);
        d["emissive_texture"] = textureRef(model, mat.emissiveTexture.index, mat.emissiveTexture.texCoord);
        d["alpha_mode"] = mat.alphaMode;
        d["alpha_cutoff"] = mat.alphaCutoff;
        d["double_sided"] = mat.doubleSided;
        nb::list extensions;
        for (const auto& [name, value] : mat.extensions) extensions.append(name);
        d["extensions"] = extensions;
        // KHR_materials_ior / KHR_materials_transmission: the two numbers a dielectric needs.
        if (auto it = mat.extensions.find("KHR_materials_ior"); it != mat.extensions.end() && it->second.Has("ior"))
            d["ior"] = it->second.Get("ior").GetNumberAsDouble();
        if (auto it = mat.extensions.find("KHR_materials_transmission");
            it != mat.extensions.end() && it->second.Has("transmissionFactor"))
            d["transmission"] = it->second.Get("transmissionFactor").GetNumberAsDouble();
        materials.append(d);
    }
    nb::list images;
    for (const tinygltf::Image& image : model.images) {
        nb::dict d;
        d["name"] = image.name;
        d["mime_type"] = image.mimeType;
        bool external = !image.uri.empty() && image.uri.rfind("data:", 0) != 0;
        d["uri"] = external ? image.uri : std::string();  // still percent-encoded
        d["bytes"] = external ? nb::bytes("", 0) : nb::bytes(reinterpret_cast<const char*>(image.image.data()), image.image.size());
        images.append(d);
    }
    nb::list roots;
    int sceneIndex = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (size_t(sceneIndex) < model.scenes.size()) {
        for (int n : model.scenes[sceneIndex].nodes) roots.append(n);
    } else {
        // No scene: every node that is nobody's child.
        std::vector<char> child(model.nodes.size(), 0);
        for (const auto& node : model.nodes)
            for (int c : node.children)
                if (c >= 0 && size_t(c) < child.size()) child[c] = 1;
        for (size_t i = 0; i < child.size(); ++i)
            if (!child[i]) roots.append(int(i));
    }
    nb::dict result;
    result["meshes"] = meshes;
    result["nodes"] = nodes;
    result["roots"] = roots;
    result["materials"] = materials;
    result["images"] = images;
    result["generator"] = model.asset.generator;
    result["copyright"] = model.asset.copyright;
    result["repaired_normals"] = repaired;
    result["warnings"] = warning;
    return result;
}

}  // namespace

void bindImport(nb::module_& m) {
    m.def("read_obj", &readObj, "path"_a,
          "Parses a Wavefront OBJ (and its MTL) into meshes per (group, material), materials and counts.");
    m.def("read_gltf", &readGltf, "path"_a,
          "Parses a glTF 2.0 file (.gltf or .glb) into meshes, nodes, materials and images.");
}
