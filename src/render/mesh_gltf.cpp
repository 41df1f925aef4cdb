// glTF 2.0 (.gltf with its buffers, .glb) through TinyGLTF (Debian's
// libtinygltf): the triangle primitives of every mesh in the default scene,
// each placed by its node's world transform (TRS or matrix), with POSITION,
// TEXCOORD_0 and NORMAL. Images are not decoded: only the geometry is read.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <strings.h>
#include <vector>

#include <tiny_gltf.h>

#include "render/mesh.h"

extern "C" {
#include "core/error.h"
}

namespace {

struct mat4 {
  double m[16]; // column-major, as glTF stores it
};

mat4 identity() {
  mat4 r{};
  r.m[0] = r.m[5] = r.m[10] = r.m[15] = 1.0;
  return r;
}

mat4 mul(const mat4 &a, const mat4 &b) {
  mat4 r{};
  for (int c = 0; c < 4; c++)
    for (int row = 0; row < 4; row++) {
      double s = 0.0;
      for (int k = 0; k < 4; k++)
        s += a.m[k * 4 + row] * b.m[c * 4 + k];
      r.m[c * 4 + row] = s;
    }
  return r;
}

mat4 local_of(const tinygltf::Node &n) {
  mat4 r = identity();
  if (n.matrix.size() == 16) {
    for (int k = 0; k < 16; k++)
      r.m[k] = n.matrix[k];
    return r;
  }
  double t[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
  if (n.translation.size() == 3)
    for (int k = 0; k < 3; k++)
      t[k] = n.translation[k];
  if (n.rotation.size() == 4)
    for (int k = 0; k < 4; k++)
      q[k] = n.rotation[k];
  if (n.scale.size() == 3)
    for (int k = 0; k < 3; k++)
      s[k] = n.scale[k];
  double x = q[0], y = q[1], z = q[2], w = q[3];
  double R[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),
                 2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                 2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y)};
  for (int c = 0; c < 3; c++)
    for (int row = 0; row < 3; row++)
      r.m[c * 4 + row] = R[c * 3 + row] * s[c];
  for (int k = 0; k < 3; k++)
    r.m[12 + k] = t[k];
  return r;
}

struct reader {
  const tinygltf::Model &model;
  const char *path;
  nbrdf_error *err;
  render_mesh *mesh;
};

// Reads element i of an accessor as `want` doubles (normalised integers per the spec).
bool accessor_view(reader &r, int index, const char *what, int want, const unsigned char **base,
                   size_t *stride, const tinygltf::Accessor **acc) {
  const tinygltf::Model &m = r.model;
  if (index < 0 || index >= (int)m.accessors.size()) {
    core_fail(r.err, NBRDF_ERR_FORMAT, "%s: %s refers to accessor %d, expected 0..%d", r.path, what,
              index, (int)m.accessors.size() - 1);
    return false;
  }
  const tinygltf::Accessor &a = m.accessors[index];
  if (a.sparse.isSparse || a.bufferView < 0 || a.bufferView >= (int)m.bufferViews.size()) {
    core_fail(r.err, NBRDF_ERR_UNSUPPORTED,
              "%s: accessor %d (%s) is sparse or has no buffer view (expected plain data)", r.path,
              index, what);
    return false;
  }
  int n = tinygltf::GetNumComponentsInType((uint32_t)a.type);
  if (want > 0 && n != want) {
    core_fail(r.err, NBRDF_ERR_FORMAT, "%s: accessor %d (%s) has %d components, expected %d",
              r.path, index, what, n, want);
    return false;
  }
  const tinygltf::BufferView &v = m.bufferViews[a.bufferView];
  int st = a.ByteStride(v);
  int es = tinygltf::GetComponentSizeInBytes((uint32_t)a.componentType) * (n > 0 ? n : 1);
  if (st <= 0 || v.buffer < 0 || v.buffer >= (int)m.buffers.size()) {
    core_fail(r.err, NBRDF_ERR_FORMAT, "%s: accessor %d (%s): bad stride or buffer", r.path, index,
              what);
    return false;
  }
  const std::vector<unsigned char> &b = m.buffers[v.buffer].data;
  size_t start = v.byteOffset + a.byteOffset;
  size_t end = a.count ? start + (a.count - 1) * (size_t)st + (size_t)es : start;
  if (end > b.size() || end > v.byteOffset + v.byteLength) {
    core_fail(r.err, NBRDF_ERR_FORMAT,
              "%s: accessor %d (%s) reaches byte %zu of buffer view %d (%zu bytes)", r.path, index,
              what, end, a.bufferView, (size_t)v.byteLength);
    return false;
  }
  *base = b.data() + start, *stride = (size_t)st, *acc = &a;
  return true;
}

double component(const unsigned char *p, int type, bool normalized) {
  switch (type) {
  case TINYGLTF_COMPONENT_TYPE_FLOAT: {
    float f;
    std::memcpy(&f, p, 4);
    return f;
  }
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
    return normalized ? p[0] / 255.0 : p[0];
  case TINYGLTF_COMPONENT_TYPE_BYTE: {
    double v = (signed char)p[0];
    return normalized ? std::fmax(v / 127.0, -1.0) : v;
  }
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
    uint16_t u;
    std::memcpy(&u, p, 2);
    return normalized ? u / 65535.0 : u;
  }
  case TINYGLTF_COMPONENT_TYPE_SHORT: {
    int16_t s;
    std::memcpy(&s, p, 2);
    return normalized ? std::fmax(s / 32767.0, -1.0) : s;
  }
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
    uint32_t u;
    std::memcpy(&u, p, 4);
    return u;
  }
  default:
    return NAN;
  }
}

bool primitive(reader &r, int mi, int pi, const mat4 &world) {
  const tinygltf::Primitive &p = r.model.meshes[mi].primitives[pi];
  char what[160];
  std::snprintf(what, sizeof what, "mesh %d ('%.60s') primitive %d", mi,
                r.model.meshes[mi].name.c_str(), pi);
  if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != -1) return true; // points, lines: no surface
  auto pos = p.attributes.find("POSITION"), tc = p.attributes.find("TEXCOORD_0"),
       nor = p.attributes.find("NORMAL");
  if (pos == p.attributes.end()) {
    core_fail(r.err, NBRDF_ERR_FORMAT, "%s: %s has no POSITION", r.path, what);
    return false;
  }
  if (tc == p.attributes.end()) {
    core_fail(r.err, NBRDF_ERR_FORMAT,
              "%s: %s has no TEXCOORD_0 (the latent texture needs a UV map; export with UVs)",
              r.path, what);
    return false;
  }
  const unsigned char *bp, *bt, *bn = nullptr;
  size_t sp, stc, sn = 0;
  const tinygltf::Accessor *ap, *at, *an = nullptr;
  std::string wp = std::string(what) + " POSITION", wt = std::string(what) + " TEXCOORD_0",
              wn = std::string(what) + " NORMAL";
  if (!accessor_view(r, pos->second, wp.c_str(), 3, &bp, &sp, &ap) ||
      !accessor_view(r, tc->second, wt.c_str(), 2, &bt, &stc, &at))
    return false;
  if (nor != p.attributes.end() && !accessor_view(r, nor->second, wn.c_str(), 3, &bn, &sn, &an))
    return false;
  if (at->count != ap->count || (an && an->count != ap->count)) {
    core_fail(r.err, NBRDF_ERR_FORMAT,
              "%s: %s: attribute counts differ (POSITION %zu, TEXCOORD_0 %zu)", r.path, what,
              ap->count, at->count);
    return false;
  }
  // Normals by the inverse transpose of the upper 3x3 (cofactors: same direction).
  const double *M = world.m;
  double C[9] = {M[5] * M[10] - M[6] * M[9], M[6] * M[8] - M[4] * M[10], M[4] * M[9] - M[5] * M[8],
                 M[2] * M[9] - M[1] * M[10], M[0] * M[10] - M[2] * M[8], M[1] * M[8] - M[0] * M[9],
                 M[1] * M[6] - M[2] * M[5],  M[2] * M[4] - M[0] * M[6],  M[0] * M[5] - M[1] * M[4]};
  double det = M[0] * C[0] + M[4] * C[1] + M[8] * C[2];
  uint32_t base = (uint32_t)r.mesh->vertices;
  for (size_t k = 0; k < ap->count; k++) {
    double x[3], t[2], nn[3] = {0, 0, 0};
    for (int c = 0; c < 3; c++)
      x[c] = component(bp + k * sp + 4 * c, ap->componentType, ap->normalized);
    int ts = tinygltf::GetComponentSizeInBytes((uint32_t)at->componentType);
    for (int c = 0; c < 2; c++)
      t[c] = component(bt + k * stc + ts * c, at->componentType, at->normalized);
    if (bn)
      for (int c = 0; c < 3; c++)
        nn[c] = component(bn + k * sn + 4 * c, an->componentType, an->normalized);
    float pw[3], uv[2] = {(float)t[0], (float)t[1]}, nw[3];
    for (int c = 0; c < 3; c++) {
      pw[c] = (float)(M[c] * x[0] + M[4 + c] * x[1] + M[8 + c] * x[2] + M[12 + c]);
      // C row c is the cofactor row; inverse transpose = C / det.
      nw[c] =
          (float)((C[c] * nn[0] + C[3 + c] * nn[1] + C[6 + c] * nn[2]) * (det < 0 ? -1.0 : 1.0));
    }
    if (!render_mesh_add_vertex(r.mesh, pw, uv, bn ? nw : nullptr)) {
      core_fail(r.err, NBRDF_ERR_MEMORY, "%s: out of memory", r.path);
      return false;
    }
  }
  bool flip = det < 0; // a mirroring transform turns the winding
  if (p.indices >= 0) {
    const unsigned char *bi;
    size_t si;
    const tinygltf::Accessor *ai;
    std::string wi = std::string(what) + " indices";
    if (!accessor_view(r, p.indices, wi.c_str(), 1, &bi, &si, &ai)) return false;
    if (ai->count % 3) {
      core_fail(r.err, NBRDF_ERR_FORMAT, "%s: %s: %zu indices, expected a multiple of 3", r.path,
                what, ai->count);
      return false;
    }
    for (size_t k = 0; k + 2 < ai->count; k += 3) {
      uint32_t v[3];
      for (int c = 0; c < 3; c++) {
        double d = component(bi + (k + c) * si, ai->componentType, false);
        if (!(d >= 0 && d < (double)ap->count)) {
          core_fail(r.err, NBRDF_ERR_FORMAT, "%s: %s: index %zu is %g, expected 0..%zu", r.path,
                    what, k + c, d, ap->count - 1);
          return false;
        }
        v[c] = base + (uint32_t)d;
      }
      if (!render_mesh_add_triangle(r.mesh, v[0], flip ? v[2] : v[1], flip ? v[1] : v[2])) {
        core_fail(r.err, NBRDF_ERR_MEMORY, "%s: out of memory", r.path);
        return false;
      }
    }
  } else {
    for (size_t k = 0; k + 2 < ap->count; k += 3)
      if (!render_mesh_add_triangle(r.mesh, base + (uint32_t)k,
                                    base + (uint32_t)(flip ? k + 2 : k + 1),
                                    base + (uint32_t)(flip ? k + 1 : k + 2))) {
        core_fail(r.err, NBRDF_ERR_MEMORY, "%s: out of memory", r.path);
        return false;
      }
  }
  return true;
}

bool node(reader &r, int ni, const mat4 &parent, int depth, int *has_normals) {
  const tinygltf::Model &m = r.model;
  if (ni < 0 || ni >= (int)m.nodes.size() || depth > 64) {
    core_fail(r.err, NBRDF_ERR_FORMAT, "%s: node %d does not exist or the hierarchy loops", r.path,
              ni);
    return false;
  }
  const tinygltf::Node &n = m.nodes[ni];
  mat4 world = mul(parent, local_of(n));
  if (n.mesh >= 0) {
    if (n.mesh >= (int)m.meshes.size()) {
      core_fail(r.err, NBRDF_ERR_FORMAT, "%s: node %d ('%.60s') refers to mesh %d, expected 0..%d",
                r.path, ni, n.name.c_str(), n.mesh, (int)m.meshes.size() - 1);
      return false;
    }
    for (size_t p = 0; p < m.meshes[n.mesh].primitives.size(); p++) {
      if (m.meshes[n.mesh].primitives[p].attributes.count("NORMAL")) *has_normals = 1;
      if (!primitive(r, n.mesh, (int)p, world)) return false;
    }
  }
  for (int c : n.children)
    if (!node(r, c, world, depth + 1, has_normals)) return false;
  return true;
}

bool skip_image(tinygltf::Image *, const int, std::string *, std::string *, int, int,
                const unsigned char *, int, void *) {
  return true; // geometry only: images stay undecoded
}

} // namespace

extern "C" nbrdf_status render_mesh_read_gltf(const char *path, render_mesh **out,
                                              nbrdf_error *err) {
  *out = nullptr;
  nbrdf_error local;
  if (!err) err = &local;
  render_mesh *m = nullptr;  // freed in the handler when tinygltf or the walk throws
  try {
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(skip_image, nullptr);
    std::string e, w;
    size_t n = std::strlen(path);
    bool glb = n >= 4 && (!strcasecmp(path + n - 4, ".glb"));
    bool ok = glb ? loader.LoadBinaryFromFile(&model, &e, &w, path)
                  : loader.LoadASCIIFromFile(&model, &e, &w, path);
    if (!ok) {
      while (!e.empty() && (e.back() == '\n' || e.back() == ' '))
        e.pop_back();
      for (char &c : e)
        if (c == '\n') c = ' ';
      return core_fail(err, NBRDF_ERR_FORMAT, "%s: not a readable glTF 2.0 %s file: %s", path,
                       glb ? "binary (.glb)" : "(.gltf)",
                       e.empty() ? "no reason given" : e.c_str());
    }
    m = render_mesh_new();
    if (!m) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
    reader r{model, path, err, m};
    int has_normals = 0;
    bool good = true;
    if (!model.scenes.empty()) {
      int s = model.defaultScene >= 0 && model.defaultScene < (int)model.scenes.size()
                  ? model.defaultScene
                  : 0;
      for (int ni : model.scenes[s].nodes)
        if (!(good = node(r, ni, identity(), 0, &has_normals))) break;
    } else {
      // No scene: every mesh once, untransformed.
      for (size_t mi = 0; good && mi < model.meshes.size(); mi++)
        for (size_t p = 0; good && p < model.meshes[mi].primitives.size(); p++) {
          if (model.meshes[mi].primitives[p].attributes.count("NORMAL")) has_normals = 1;
          good = primitive(r, (int)mi, (int)p, identity());
        }
    }
    nbrdf_status st = good ? NBRDF_OK : err->status;
    if (st == NBRDF_OK && m->triangles == 0)
      st = core_fail(err, NBRDF_ERR_FORMAT,
                     "%s: no triangles in the default scene (expected a mesh with TRIANGLES "
                     "primitives)",
                     path);
    return render_mesh_deliver(st, m, has_normals, path, out, err);
  } catch (const std::exception &x) {
    if (m && !*out) render_mesh_free(m);
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: %s", path, x.what());
  }
}
