/* Network specs: costs of the paper's configurations, tensor layout, JSON round trip, and
 * refusal of invalid specs with a message that says what is wrong. */
#include <stdlib.h>
#include <string.h>

#include "nn/nn.h"
#include "testing.h"

static void test_paper_costs(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_spec s;
  /* Released decoder: 38 inputs, width 256, 8 residual blocks alternating with 8 plain
   * layers, plain 256 -> 1 output: about 1.06 M multiply-adds (issue 3). */
  CHECK_OK(nn_spec_resmlp(&s, 38, 256, 8, 1, 1, err), err);
  CHECK(s.n_layers == 18);
  CHECK(nn_spec_macs(&s) == 38 * 256 + 8 * (2 * 256 * 128) + 8 * 256 * 256 + 256);
  CHECK(nn_spec_macs(&s) == 1058560);
  size_t plain_in = 38 * 256 + 3 * 256, res = 2 * 256 * 128 + 3 * 128 + 3 * 256;
  size_t plain = 256 * 256 + 3 * 256, out = 257;
  CHECK(nn_spec_param_count(&s) == plain_in + 8 * res + 8 * plain + out);
  CHECK(nn_spec_outputs(&s) == 1);
  /* Layering network: 66 inputs, width 512, 4 blocks, 32 outputs. */
  CHECK_OK(nn_spec_resmlp(&s, 66, 512, 4, 0, 32, err), err);
  CHECK(nn_spec_macs(&s) == 66 * 512 + 4 * 2 * 512 * 256 + 512 * 32);
  CHECK(nn_spec_outputs(&s) == 32);
  /* A projected skip costs its GEMM; an identity skip costs nothing. */
  nn_spec t;
  nn_spec_init(&t, 10);
  int a = nn_spec_add(&t, NBRDF_NN_PLAIN, 16);
  int b = nn_spec_add(&t, NBRDF_NN_PLAIN, 16);
  nn_spec_skip(&t, b, 0);
  int c = nn_spec_add(&t, NBRDF_NN_RESIDUAL, 0);
  nn_spec_skip(&t, c, a + 1);
  CHECK_OK(nn_spec_validate(&t, err), err);
  CHECK(nn_spec_macs(&t) == 10 * 16 + (16 * 16 + 10 * 16) + 2 * 16 * 8);
}

static void test_tensor_layout(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_spec s;
  CHECK_OK(nn_spec_resmlp(&s, 38, 256, 8, 1, 1, err), err);
  nn_spec_skip(&s, 5, 0);
  nn_network *nn = NULL;
  CHECK_OK(nn_create(&s, &nn, err), err);
  CHECK(nn_inputs(nn) == 38 && nn_outputs(nn) == 1);
  CHECK(nn_param_count(nn) == nn_spec_param_count(&s));
  /* Tensors tile the parameter array in order, without gaps. */
  size_t at = 0;
  for (int k = 0; k < nn_tensor_count(nn); k++) {
    const nn_tensor *t = nn_tensor_at(nn, k);
    CHECK_MSG(t->offset == at, "%s at %zu, expected %zu", t->name, t->offset, at);
    CHECK(t->count == (size_t)t->rows * (size_t)t->cols);
    CHECK(nn_find_tensor(nn, t->name) == t);
    at += t->count;
  }
  CHECK(at == nn_param_count(nn));
  CHECK(nn_tensor_at(nn, -1) == NULL);
  CHECK(nn_tensor_at(nn, nn_tensor_count(nn)) == NULL);
  CHECK(nn_find_tensor(nn, "layers.99.weight") == NULL);
  const nn_tensor *t = nn_find_tensor(nn, "layers.1.fc1.weight");
  CHECK(t && t->rank == 2 && t->rows == 128 && t->cols == 256);
  t = nn_find_tensor(nn, "layers.1.norm2.bias");
  CHECK(t && t->rank == 1 && t->rows == 256 && t->cols == 1);
  t = nn_find_tensor(nn, "layers.0.fc.weight");
  CHECK(t && t->rows == 256 && t->cols == 38);
  t = nn_find_tensor(nn, "layers.5.skip.weight"); /* 38 -> 256 needs a projection */
  CHECK(t && t->rows == 256 && t->cols == 38);
  t = nn_find_tensor(nn, "layers.17.weight");
  CHECK(t && t->rows == 1 && t->cols == 256);
  CHECK(((uintptr_t)nn_params(nn) & 63) == 0);
  nn_destroy(nn);
}

static void test_init(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_spec s;
  CHECK_OK(nn_spec_resmlp(&s, 20, 64, 2, 1, 3, err), err);
  nn_network *a = NULL, *b = NULL;
  CHECK_OK(nn_create(&s, &a, err), err);
  CHECK_OK(nn_create(&s, &b, err), err);
  size_t n = nn_param_count(a);
  nn_init_params(a, 42);
  nn_init_params(b, 42);
  CHECK(memcmp(nn_params(a), nn_params(b), n * sizeof(float)) == 0);
  nn_init_params(b, 43);
  CHECK(memcmp(nn_params(a), nn_params(b), n * sizeof(float)) != 0);
  const float *p = nn_params(a);
  for (int k = 0; k < nn_tensor_count(a); k++) {
    const nn_tensor *t = nn_tensor_at(a, k);
    const float *v = p + t->offset;
    if (t->rank == 1) {
      float want = strstr(t->name, "norm") && strstr(t->name, ".weight") ? 1.0f : 0.0f;
      for (size_t i = 0; i < t->count; i++)
        CHECK_MSG(v[i] == want, "%s[%zu]", t->name, i);
      continue;
    }
    /* He uniform for weights feeding a ReLU, LeCun uniform for the output layer: the sample
     * standard deviation is bound / sqrt(3). */
    int is_output = strcmp(t->name, "layers.5.weight") == 0;
    double bound = sqrt((is_output ? 3.0 : 6.0) / t->cols), sum2 = 0;
    for (size_t i = 0; i < t->count; i++) {
      CHECK(fabs(v[i]) <= bound);
      sum2 += (double)v[i] * v[i];
    }
    double sd = sqrt(sum2 / t->count), want = bound / sqrt(3.0);
    if (t->count >= 1000) CHECK_REL(sd, want, 0.05, 0);
    if (is_output) CHECK_REL(sd, want, 0.3, 0);
  }
  nn_destroy(a);
  nn_destroy(b);
}

static void test_json_round_trip(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_spec s, r;
  CHECK_OK(nn_spec_resmlp(&s, 38, 64, 3, 1, 1, err), err);
  s.layers[3].hidden = 24;
  nn_spec_skip(&s, 3, 0);
  nn_spec_skip(&s, 4, 2);
  int i = nn_spec_add(&s, NBRDF_NN_RELU, 0);
  CHECK(i == s.n_layers - 1);
  char *json = NULL, *again = NULL;
  CHECK_OK(nn_spec_to_json(&s, &json, err), err);
  CHECK(json && strstr(json, "\"format\":\"nbrdf-nn\""));
  CHECK(json && strstr(json, "{\"kind\":\"residual\",\"hidden\":24,\"skip\":0}"));
  CHECK_OK(nn_spec_from_json(json, &r, err), err);
  CHECK(memcmp(&s, &r, sizeof s) == 0);
  CHECK_OK(nn_spec_to_json(&r, &again, err), err);
  CHECK(json && again && strcmp(json, again) == 0);
  free(json);
  free(again);
  /* Whitespace and key order do not matter. */
  const char *pretty = "{ \"layers\": [ {\"width\": 8, \"kind\": \"plain\"},\n"
                       "  {\"kind\": \"linear\", \"skip\": 0, \"width\": 2} ],\n"
                       "  \"inputs\": 3, \"version\": 1, \"format\": \"nbrdf-nn\" }";
  CHECK_OK(nn_spec_from_json(pretty, &r, err), err);
  CHECK(r.n_inputs == 3 && r.n_layers == 2 && r.layers[1].has_skip && r.layers[1].width == 2);
}

static void refused(const char *json, const char *needle) {
  nbrdf_error err_s, *err = &err_s;
  nn_spec s;
  nn_spec_init(&s, 77);
  CHECK_FAILS(nn_spec_from_json(json, &s, err), NBRDF_ERR_FORMAT, err, needle);
  CHECK_MSG(s.n_inputs == 77, "spec changed by a refused JSON: %s", json);
}

#define HEAD "{\"format\":\"nbrdf-nn\",\"version\":1,"

static void test_json_invalid(void) {
  refused("not json", "invalid JSON");
  refused("[1,2]", "expected a JSON object");
  refused("{\"format\":\"other\",\"version\":1,\"inputs\":3,\"layers\":[]}", "\"format\"");
  refused("{\"format\":\"nbrdf-nn\",\"version\":2,\"inputs\":3,\"layers\":[]}",
          "version 2 is not supported");
  refused(HEAD "\"layers\":[{\"kind\":\"relu\"}]}", "\"inputs\" must be a number");
  refused(HEAD "\"inputs\":0,\"layers\":[{\"kind\":\"relu\"}]}", "\"inputs\" = 0");
  refused(HEAD "\"inputs\":2.5,\"layers\":[{\"kind\":\"relu\"}]}", "integer");
  refused(HEAD "\"inputs\":3,\"layers\":{}}", "\"layers\" missing or not an array");
  refused(HEAD "\"inputs\":3,\"layers\":[]}", "no layers");
  refused(HEAD "\"inputs\":3,\"layers\":[{\"kind\":\"conv\"}]}", "unknown kind \"conv\"");
  refused(HEAD "\"inputs\":3,\"layers\":[{\"kind\":7}]}", "\"kind\" missing");
  refused(HEAD "\"inputs\":3,\"layers\":[3]}", "layer 0: expected an object");
  refused(HEAD "\"inputs\":3,\"layers\":[{\"kind\":\"relu\",\"size\":3}]}",
          "layer 0: unknown key \"size\"");
  refused(HEAD "\"inputs\":3,\"layers\":[{\"kind\":\"relu\"}],\"extra\":1}",
          "unknown key \"extra\"");
  refused(HEAD "\"inputs\":3,\"layers\":[{\"kind\":\"linear\"}]}", "layer 0 (linear): width = 0");
  refused(HEAD "\"inputs\":3,\"layers\":[{\"kind\":\"linear\",\"width\":-4}]}", "\"width\" = -4");
  refused(HEAD "\"inputs\":4,\"layers\":[{\"kind\":\"residual\",\"width\":8}]}",
          "differs from its input width 4");
  refused(HEAD "\"inputs\":4,\"layers\":[{\"kind\":\"plain\",\"width\":4,\"skip\":3}]}",
          "skip from activation 3");
  refused(HEAD "\"inputs\":1,\"layers\":[{\"kind\":\"layernorm\"}]}", "too small for LayerNorm");
  refused(HEAD "\"inputs\":4,\"layers\":[{\"kind\":\"plain\",\"width\":1}]}",
          "too small for LayerNorm");
  refused(HEAD "\"inputs\":4,\"layers\":[{\"kind\":\"relu\",\"skip\":0}]}",
          "layer 0 (relu) cannot take a skip connection");
  refused(HEAD "\"inputs\":4,\"layers\":[{\"kind\":\"plain\",\"width\":4,\"hidden\":2}]}",
          "only meaningful for residual");
  refused(HEAD "\"inputs\":3,\"layers\":[{\"kind\":\"residual\"}]}", "hidden width 1");
}

static void test_validate(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_spec s;
  nn_spec_init(&s, 4);
  CHECK_FAILS(nn_spec_validate(&s, err), NBRDF_ERR_ARGUMENT, err, "no layers");
  for (int i = 0; i < NBRDF_NN_MAX_LAYERS; i++)
    CHECK(nn_spec_add(&s, NBRDF_NN_RELU, 0) == i);
  CHECK_OK(nn_spec_validate(&s, err), err);
  CHECK(nn_spec_add(&s, NBRDF_NN_RELU, 0) == -1);
  CHECK_FAILS(nn_spec_validate(&s, err), NBRDF_ERR_ARGUMENT, err, "more than 64 layers");
  CHECK_FAILS(nn_spec_resmlp(&s, 4, 8, 40, 1, 1, err), NBRDF_ERR_ARGUMENT, err, "at most 64");
  nn_spec_init(&s, 4);
  nn_spec_add(&s, (nn_kind)99, 3);
  CHECK_FAILS(nn_spec_validate(&s, err), NBRDF_ERR_ARGUMENT, err, "unknown kind 99");
  nn_network *nn = NULL;
  CHECK_FAILS(nn_create(&s, &nn, err), NBRDF_ERR_ARGUMENT, err, "unknown kind");
  CHECK(nn == NULL);
  CHECK_FAILS(nn_spec_to_json(&s, &(char *){NULL}, err), NBRDF_ERR_ARGUMENT, err, "unknown kind");
  CHECK(nn_kind_name((nn_kind)0) == NULL);
}

int main(void) {
  RUN(test_paper_costs);
  RUN(test_tensor_layout);
  RUN(test_init);
  RUN(test_json_round_trip);
  RUN(test_json_invalid);
  RUN(test_validate);
  return testing_finish();
}
