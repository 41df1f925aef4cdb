/* The mesh readers on small files written here (OBJ with polygons and
 * negative indices, ASCII and binary PLY, glTF .gltf + .bin and .glb with a
 * node transform), their errors (file and line or glTF item, what was
 * expected; no UVs refused), and the BVH against brute force. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "render/mesh.h"
#include "render/mesh_bvh.h"
#include "testing.h"

static render_mesh *load(const char *name, nbrdf_status want, const char *msg) {
  render_mesh *m = NULL;
  nbrdf_error err = {NBRDF_OK, ""};
  nbrdf_status st = render_mesh_load(testing_path(name), &m, &err);
  CHECK_MSG(st == want, "%s: %s (%s)", name, nbrdf_status_name(st), err.message);
  if (msg)
    CHECK_MSG(strstr(err.message, msg), "%s: message '%s' lacks '%s'", name, err.message, msg);
  return m;
}

static void test_obj(void) {
  /* A quad (fan-triangulated) and a triangle by negative indices; vt flipped to 1 - v. */
  testing_write_text(testing_path("q.obj"), "# quad\n"
                                            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                            "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                            "vn 0 0 1\n"
                                            "o thing\ns off\n"
                                            "f 1/1/1 2/2/1 3/3/1 4/4/1\n"
                                            "f -4/-4/-1 -2/-2/-1 -1/-1/-1\n");
  render_mesh *m = load("q.obj", NBRDF_OK, NULL);
  if (!m) return;
  CHECK(m->triangles == 3);
  CHECK(m->vertices == 4);                 /* corners shared */
  CHECK_NEAR(m->uv[2 * 2 + 1], 0.0, 1e-7); /* vt (1, 1) -> v from the top 0 */
  CHECK_NEAR(m->uv[2 * 0 + 1], 1.0, 1e-7);
  CHECK_NEAR(m->n[2], 1.0, 1e-7);
  CHECK_NEAR(m->hi[0], 1.0, 0);
  CHECK_NEAR(m->lo[1], 0.0, 0);
  render_mesh_free(m);
  testing_write_text(testing_path("nouv.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  load("nouv.obj", NBRDF_ERR_FORMAT, "nouv.obj:4: face corner '1' has no texture coordinate");
  testing_write_text(testing_path("bad.obj"), "v 0 0 0\nvt 0 0\nv 1 0\n");
  load("bad.obj", NBRDF_ERR_FORMAT, "bad.obj:3: 'v' expects 3 number(s)");
  testing_write_text(testing_path("range.obj"), "v 0 0 0\nvt 0 0\nf 1/1 2/1 1/1\n");
  load("range.obj", NBRDF_ERR_FORMAT, "range.obj:3: face corner '2/1' refers to vertex 2");
  load("missing.obj", NBRDF_ERR_IO, "missing.obj: cannot open");
  testing_write_text(testing_path("x.stl"), "solid\n");
  load("x.stl", NBRDF_ERR_ARGUMENT, "expected .gltf, .glb, .ply or .obj");
}

static const char ply_head[] = "ply\nformat %s 1.0\ncomment made by test_mesh\n"
                               "element vertex 4\nproperty float x\nproperty float y\n"
                               "property float z\nproperty uchar red\nproperty float s\n"
                               "property float t\nelement face 1\n"
                               "property list uchar int vertex_indices\nend_header\n";

static void test_ply(void) {
  char text[2048];
  snprintf(text, sizeof text, ply_head, "ascii");
  strcat(text, "0 0 0 255 0 0\n1 0 0 0 1 0\n1 1 0 0 1 1\n0 1 0 0 0 1\n4 0 1 2 3\n");
  testing_write_text(testing_path("a.ply"), text);
  render_mesh *m = load("a.ply", NBRDF_OK, NULL);
  if (m) {
    CHECK(m->triangles == 2 && m->vertices == 4);
    CHECK_NEAR(m->uv[2 * 2], 1.0, 0);
    CHECK_NEAR(m->uv[2 * 2 + 1], 0.0, 0);
    CHECK_NEAR(m->n[2], 1.0, 1e-6); /* from the faces */
  }
  render_mesh_free(m);
  /* The same as binary little-endian. */
  FILE *f = fopen(testing_path("b.ply"), "wb");
  CHECK(f != NULL);
  if (f) {
    fprintf(f, ply_head, "binary_little_endian");
    const float p[4][5] = {{0, 0, 0, 0, 0}, {1, 0, 0, 1, 0}, {1, 1, 0, 1, 1}, {0, 1, 0, 0, 1}};
    for (int v = 0; v < 4; v++) {
      unsigned char red = 7;
      fwrite(p[v], 4, 3, f), fwrite(&red, 1, 1, f), fwrite(p[v] + 3, 4, 2, f);
    }
    unsigned char n = 4;
    int idx[4] = {0, 1, 2, 3};
    fwrite(&n, 1, 1, f), fwrite(idx, 4, 4, f);
    fclose(f);
  }
  m = load("b.ply", NBRDF_OK, NULL);
  if (m) {
    CHECK(m->triangles == 2 && m->vertices == 4);
    CHECK_NEAR(m->p[3 * 2 + 1], 1.0, 0);
    CHECK_NEAR(m->uv[2 * 3 + 1], 0.0, 0);
  }
  render_mesh_free(m);
  /* Truncated binary data, a bad ASCII value, no UVs. */
  f = fopen(testing_path("short.ply"), "wb");
  if (f) fprintf(f, ply_head, "binary_little_endian"), fwrite("abcd", 1, 4, f), fclose(f);
  load("short.ply", NBRDF_ERR_FORMAT, "binary data ends at byte");
  snprintf(text, sizeof text, ply_head, "ascii");
  strcat(text, "0 0 0 255 0 0\n1 0 zero 0 1 0\n");
  testing_write_text(testing_path("c.ply"), text);
  load("c.ply", NBRDF_ERR_FORMAT, "c.ply:15: 'zero' is not a number");
  testing_write_text(testing_path("nouv.ply"),
                     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                     "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                     "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  load("nouv.ply", NBRDF_ERR_FORMAT, "no texture coordinates");
}

/* One triangle: positions, UVs, uint16 indices, in a buffer `bin` of 32 + 24 + 6 bytes. */
static size_t tri_buffer(unsigned char *bin) {
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0}, uv[6] = {0, 0, 1, 0, 0, 1};
  const unsigned short idx[3] = {0, 1, 2};
  memcpy(bin, p, 36), memcpy(bin + 36, uv, 24), memcpy(bin + 60, idx, 6);
  return 66;
}

static const char gltf_json[] =
    "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
    "\"nodes\":[{\"mesh\":0,\"translation\":[0,0,5],\"scale\":[2,2,2]}],"
    "\"meshes\":[{\"name\":\"Tri\",\"primitives\":[{\"attributes\":{\"POSITION\":0%s},"
    "\"indices\":2}]}],"
    "\"buffers\":[{%s\"byteLength\":66}],"
    "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},"
    "{\"buffer\":0,\"byteOffset\":36,\"byteLength\":24},"
    "{\"buffer\":0,\"byteOffset\":60,\"byteLength\":6}],"
    "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
    "\"min\":[0,0,0],\"max\":[1,1,0]},"
    "{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC2\"},"
    "{\"bufferView\":2,\"componentType\":5123,\"count\":3,\"type\":\"SCALAR\"}]}";

static void put32(FILE *f, unsigned v) {
  unsigned char b[4] = {(unsigned char)v, (unsigned char)(v >> 8), (unsigned char)(v >> 16),
                        (unsigned char)(v >> 24)};
  fwrite(b, 1, 4, f);
}

static void test_gltf(void) {
  unsigned char bin[80] = {0};
  size_t n = tri_buffer(bin);
  FILE *f = fopen(testing_path("tri.bin"), "wb");
  if (f) fwrite(bin, 1, n, f), fclose(f);
  char json[4096];
  snprintf(json, sizeof json, gltf_json, ",\"TEXCOORD_0\":1", "\"uri\":\"tri.bin\",");
  testing_write_text(testing_path("tri.gltf"), json);
  render_mesh *m = load("tri.gltf", NBRDF_OK, NULL);
  if (m) {
    CHECK(m->triangles == 1 && m->vertices == 3);
    /* translation (0, 0, 5) after scale 2 */
    CHECK_NEAR(m->p[3 * 1 + 0], 2.0, 1e-6);
    CHECK_NEAR(m->p[3 * 1 + 2], 5.0, 1e-6);
    CHECK_NEAR(m->uv[2 * 2 + 1], 1.0, 0); /* glTF's v as stored */
    CHECK_NEAR(m->n[2], 1.0, 1e-6);
  }
  render_mesh_free(m);
  /* The same as .glb: header, JSON chunk (padded with spaces), BIN chunk. */
  snprintf(json, sizeof json, gltf_json, ",\"TEXCOORD_0\":1", "");
  size_t jl = strlen(json), jp = (jl + 3) & ~(size_t)3, bp = (n + 3) & ~(size_t)3;
  f = fopen(testing_path("tri.glb"), "wb");
  if (f) {
    fwrite("glTF", 1, 4, f), put32(f, 2), put32(f, (unsigned)(12 + 8 + jp + 8 + bp));
    put32(f, (unsigned)jp), fwrite("JSON", 1, 4, f), fwrite(json, 1, jl, f);
    for (size_t k = jl; k < jp; k++)
      fputc(' ', f);
    put32(f, (unsigned)bp), fwrite("BIN\0", 1, 4, f), fwrite(bin, 1, bp, f);
    fclose(f);
  }
  m = load("tri.glb", NBRDF_OK, NULL);
  if (m) CHECK(m->triangles == 1 && m->vertices == 3);
  render_mesh_free(m);
  /* No TEXCOORD_0: named by mesh and primitive. */
  snprintf(json, sizeof json, gltf_json, "", "\"uri\":\"tri.bin\",");
  testing_write_text(testing_path("nouv.gltf"), json);
  load("nouv.gltf", NBRDF_ERR_FORMAT, "mesh 0 ('Tri') primitive 0 has no TEXCOORD_0");
  testing_write_text(testing_path("junk.gltf"), "{\"asset\": ");
  load("junk.gltf", NBRDF_ERR_FORMAT, "junk.gltf: not a readable glTF 2.0");
}

static void test_bvh(void) {
  /* A torus-like cloud of random triangles; 2000 random rays, closest hits and occlusion. */
  render_mesh *m = render_mesh_new();
  core_rng r;
  core_rng_init(&r, 5, 0);
  for (int t = 0; t < 3000; t++) {
    vec3 c = v3(4 * core_rng_uniform(&r) - 2, 4 * core_rng_uniform(&r) - 2,
                4 * core_rng_uniform(&r) - 2);
    for (int k = 0; k < 3; k++) {
      float p[3] = {(float)(c.x + 0.2 * core_rng_uniform(&r)),
                    (float)(c.y + 0.2 * core_rng_uniform(&r)),
                    (float)(c.z + 0.2 * core_rng_uniform(&r))},
            uv[2] = {0, 0};
      CHECK(render_mesh_add_vertex(m, p, uv, NULL));
    }
    CHECK(render_mesh_add_triangle(m, 3 * t, 3 * t + 1, 3 * t + 2));
  }
  nbrdf_error err;
  CHECK_OK(render_mesh_finish(m, 0, "cloud", &err), &err);
  render_bvh *b = NULL;
  CHECK_OK(render_bvh_build(m, &b, &err), &err);
  if (!b) return render_mesh_free(m);
  CHECK(render_bvh_nodes(b) < 2 * m->triangles);
  int hits = 0;
  for (int k = 0; k < 2000; k++) {
    vec3 o = v3(6 * core_rng_uniform(&r) - 3, 6 * core_rng_uniform(&r) - 3,
                6 * core_rng_uniform(&r) - 3);
    vec3 d = v3_normalize(
        v3(core_rng_uniform(&r) - 0.5, core_rng_uniform(&r) - 0.5, core_rng_uniform(&r) - 0.5));
    render_ray_hit best = {-1, 1e30, 0, 0}, h;
    for (int t = 0; t < m->triangles; t++)
      if (render_triangle_intersect(m, t, o, d, 0.0, best.t, &h)) best = h;
    render_ray_hit got = {-1, 0, 0, 0};
    int hit = render_bvh_intersect(b, o, d, 0.0, 1e30, &got);
    CHECK_MSG(hit == (best.tri >= 0), "ray %d: BVH %s, brute force %s", k, hit ? "hit" : "miss",
              best.tri >= 0 ? "hit" : "miss");
    if (hit && best.tri >= 0) {
      hits++;
      CHECK_NEAR(got.t, best.t, 1e-5 * (1 + best.t));
      CHECK(render_bvh_occluded(b, o, d, 0.0, best.t * 1.001));
      CHECK(!render_bvh_occluded(b, o, d, 0.0, best.t * 0.999));
    }
  }
  CHECK(hits > 200); /* the rays do meet the cloud */
  render_bvh_free(b);
  render_mesh_free(m);
}

int main(void) {
  RUN(test_obj);
  RUN(test_ply);
  RUN(test_gltf);
  RUN(test_bvh);
  return testing_finish();
}
