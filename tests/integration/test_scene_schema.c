/*
 * test_scene_schema.c - proto/scene.schema.json describes the scene documents refractd
 * accepts: at every level of the document (root, camera, render, environment, lights of
 * each type, receiver, lightsim, object, bounds, transform, brdf, each shape, each GRIN
 * profile, volume layers), the keys the schema
 * lists are exactly the keys the daemon allows. The daemon says which keys it allows when
 * it meets an unknown one ("...; allowed: a, b, c"), so each case sends a valid document
 * with one unknown key at that level and compares the two sets.
 */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "daemon.h"
#include "test.h"

#define BOUNDS "\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}"
#define OBJ_WITH(extra) "{\"objects\": [{" BOUNDS ", \"resolution\": 8, " extra "}]}"
#define UNKNOWN "\"zz_unknown\": 1"

struct schema_case {
    const char *where;
    const char *pointers[3]; /* schema objects whose "properties" together are the keys */
    const char *document;    /* valid but for UNKNOWN at that level */
};

/* clang-format off */
static const struct schema_case cases[] = {
    {"root", {"", NULL}, "{" UNKNOWN ", \"objects\": [{" BOUNDS ", \"resolution\": 8, \"ior\": 1.5}]}"},
    {"camera", {"/properties/camera", NULL},
     "{\"camera\": {" UNKNOWN "}, \"objects\": [{" BOUNDS ", \"resolution\": 8, \"ior\": 1.5}]}"},
    {"render", {"/properties/render", NULL},
     "{\"render\": {" UNKNOWN "}, \"objects\": [{" BOUNDS ", \"resolution\": 8, \"ior\": 1.5}]}"},
    {"environment", {"/properties/environment", NULL},
     "{\"environment\": {" UNKNOWN "}, \"objects\": [{" BOUNDS ", \"resolution\": 8, \"ior\": 1.5}]}"},
    {"object", {"/$defs/object", NULL}, OBJ_WITH("\"ior\": 1.5, " UNKNOWN)},
    {"bounds", {"/$defs/object/properties/bounds", NULL},
     "{\"objects\": [{\"bounds\": {\"min\": [0, 0, 0], \"max\": [1, 1, 1], " UNKNOWN "}, "
     "\"resolution\": 8, \"ior\": 1.5}]}"},
    {"transform", {"/$defs/object/properties/transform", NULL},
     OBJ_WITH("\"ior\": 1.5, \"transform\": {" UNKNOWN "}")},
    {"transform.rotate", {"/$defs/object/properties/transform/properties/rotate", NULL},
     OBJ_WITH("\"ior\": 1.5, \"transform\": {\"rotate\": {\"axis\": [0, 1, 0], \"angle_deg\": 5, "
              UNKNOWN "}}")},
    {"sphere surface", {"/$defs/shape_sphere", "/$defs/surface", NULL},
     "{\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 0.5, \"medium\": {\"ior\": 1.5}, " UNKNOWN "}]}"},
    {"lathe surface", {"/$defs/shape_lathe", "/$defs/surface", NULL},
     "{\"surfaces\": [{\"shape\": \"lathe\", \"profile\": [[0, 0], [0.5, 0], [0.5, 0.5], [0, 0.5]], "
     "\"medium\": {\"ior\": 1.5}, " UNKNOWN "}]}"},
    {"plane surface", {"/$defs/shape_plane", "/$defs/surface", NULL},
     "{\"surfaces\": [{\"shape\": \"plane\", \"normal\": [0, 1, 0], \"medium\": {\"ior\": 1.33}, " UNKNOWN "}]}"},
    {"medium", {"/$defs/medium", NULL},
     "{\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 0.5, \"medium\": {\"ior\": 1.5, " UNKNOWN "}}]}"},
    {"sphere in ior", {"/$defs/shape_sphere", "/$defs/ior_shape_layer", NULL},
     OBJ_WITH("\"ior\": {\"shape\": \"sphere\", \"radius\": 0.5, \"inside\": 1.5, " UNKNOWN "}")},
    {"box in attenuation", {"/$defs/shape_box", "/$defs/attenuation_shape_layer", NULL},
     OBJ_WITH("\"attenuation\": {\"shape\": \"box\", \"size\": [1, 1, 1], \"inside\": 0.5, " UNKNOWN "}")},
    {"rounded_box in emission", {"/$defs/shape_rounded_box", "/$defs/emission_shape_layer", NULL},
     OBJ_WITH("\"emission\": {\"shape\": \"rounded_box\", \"size\": [1, 1, 1], \"radius\": 0.1, "
              "\"inside\": 0.5, " UNKNOWN "}")},
    {"cylinder in opaque", {"/$defs/shape_cylinder", "/$defs/opaque_shape_layer", NULL},
     OBJ_WITH("\"opaque\": {\"shape\": \"cylinder\", \"radius\": 0.3, \"height\": 1, \"axis\": \"z\", "
              "\"inside\": 0.5, " UNKNOWN "}")},
    {"lathe in ior", {"/$defs/shape_lathe", "/$defs/ior_shape_layer", NULL},
     OBJ_WITH("\"ior\": {\"shape\": \"lathe\", \"axis\": \"y\", \"profile\": [[0, 0], [0.5, 0], "
              "[0.5, 0.5], [0, 0.5]], \"inside\": 1.5, " UNKNOWN "}")},
    {"text in ior", {"/$defs/shape_text", "/$defs/ior_shape_layer", NULL},
     OBJ_WITH("\"ior\": {\"shape\": \"text\", \"text\": \"AB\", \"height\": 0.3, \"depth\": 0.2, "
              "\"inside\": 1.5, " UNKNOWN "}")},
    {"luneburg", {"/$defs/profile_luneburg", NULL},
     OBJ_WITH("\"ior\": {\"profile\": \"luneburg\", \"radius\": 1, " UNKNOWN "}")},
    {"maxwell_fisheye", {"/$defs/profile_maxwell_fisheye", NULL},
     OBJ_WITH("\"ior\": {\"profile\": \"maxwell_fisheye\", \"radius\": 1, " UNKNOWN "}")},
    {"linear", {"/$defs/profile_linear", NULL},
     OBJ_WITH("\"ior\": {\"profile\": \"linear\", \"gradient\": [0, 0.1, 0], " UNKNOWN "}")},
    {"gaussian", {"/$defs/profile_gaussian", NULL},
     OBJ_WITH("\"ior\": {\"profile\": \"gaussian\", \"n_peak\": 1.5, \"sigma\": 0.3, " UNKNOWN "}")},
    {"volume layer", {"/$defs/volume_layer", NULL},
     OBJ_WITH("\"ior\": {\"volume\": \"v\", " UNKNOWN "}")},
    {"bumpy_sphere in scattering", {"/$defs/shape_bumpy_sphere", "/$defs/scattering_shape_layer", NULL},
     OBJ_WITH("\"scattering\": {\"shape\": \"bumpy_sphere\", \"radius\": 0.5, \"inside\": 0.5, " UNKNOWN "}")},
    {"box in anisotropy", {"/$defs/shape_box", "/$defs/anisotropy_shape_layer", NULL},
     OBJ_WITH("\"scattering\": 1, \"anisotropy\": {\"shape\": \"box\", \"size\": [1, 1, 1], "
              "\"inside\": 0.5, " UNKNOWN "}")},
    {"brdf", {"/$defs/brdf", NULL}, OBJ_WITH("\"ior\": 1.5, \"brdf\": {" UNKNOWN "}")},
    {"particles milk", {"/$defs/particles/oneOf/0", NULL},
     OBJ_WITH("\"particles\": {\"preset\": \"milk\", \"fat_percent\": 1, " UNKNOWN "}")},
    {"particles water", {"/$defs/particles/oneOf/1", NULL},
     OBJ_WITH("\"particles\": {\"preset\": \"water\", " UNKNOWN "}")},
    {"particles explicit", {"/$defs/particles/oneOf/2", NULL},
     OBJ_WITH("\"particles\": {\"populations\": [], " UNKNOWN "}")},
    {"particle population", {"/$defs/particle_population", NULL},
     OBJ_WITH("\"particles\": {\"populations\": [{\"ior\": 1.5, " UNKNOWN "}]}")},
    {"particle lognormal", {"/$defs/particle_population/properties/lognormal", NULL},
     OBJ_WITH("\"particles\": {\"populations\": [{\"ior\": 1.5, \"volume_fraction\": 0.01, "
              "\"lognormal\": {" UNKNOWN "}}]}")},
    {"particle power_law", {"/$defs/particle_population/properties/power_law", NULL},
     OBJ_WITH("\"particles\": {\"populations\": [{\"ior\": 1.5, \"volume_fraction\": 0.01, "
              "\"power_law\": {" UNKNOWN "}}]}")},
    {"particle region sphere", {"/$defs/shape_sphere", NULL},
     OBJ_WITH("\"particles\": {\"preset\": \"water\", \"region\": {\"shape\": \"sphere\", "
              "\"radius\": 0.5, " UNKNOWN "}}")},
    {"directional light", {"/$defs/light_directional", NULL},
     "{\"lights\": [{\"type\": \"directional\", \"direction\": [0, -1, 0], " UNKNOWN "}], "
     "\"objects\": [{" BOUNDS ", \"resolution\": 8, \"ior\": 1.5}]}"},
    {"point light", {"/$defs/light_point", NULL},
     "{\"lights\": [{\"type\": \"point\", \"position\": [0, 2, 0], " UNKNOWN "}], "
     "\"objects\": [{" BOUNDS ", \"resolution\": 8, \"ior\": 1.5}]}"},
    {"spot light", {"/$defs/light_spot", NULL},
     "{\"lights\": [{\"type\": \"spot\", \"position\": [0, 2, 0], \"direction\": [0, -1, 0], "
     UNKNOWN "}], \"objects\": [{" BOUNDS ", \"resolution\": 8, \"ior\": 1.5}]}"},
    {"receiver", {"/properties/receiver", NULL},
     "{\"receiver\": {\"height\": -1, " UNKNOWN "}, \"objects\": [{" BOUNDS ", \"resolution\": 8, \"ior\": 1.5}]}"},
    {"lightsim", {"/properties/lightsim", NULL},
     "{\"lightsim\": {" UNKNOWN "}, \"objects\": [{" BOUNDS ", \"resolution\": 8, \"ior\": 1.5}]}"},
};
/* clang-format on */

/* Follows a JSON pointer ("/a/b", "/a/oneOf/0"; "" is the root) through objects and
 * arrays. */
static const cJSON *at_pointer(const cJSON *root, const char *pointer)
{
    const cJSON *node = root;
    char key[128];
    while (node && *pointer == '/') {
        pointer++;
        size_t n = strcspn(pointer, "/");
        snprintf(key, sizeof key, "%.*s", (int)n, pointer);
        node = cJSON_IsArray(node) ? cJSON_GetArrayItem(node, atoi(key))
                                   : cJSON_GetObjectItemCaseSensitive(node, key);
        pointer += n;
    }
    return node;
}

/* Appends the keys of node.properties to list (", "-joined, sorted later). */
static int schema_keys(const cJSON *schema, const char *const *pointers, char keys[][64], int max)
{
    int n = 0;
    for (int p = 0; p < 3 && pointers[p]; p++) {
        const cJSON *props =
            cJSON_GetObjectItemCaseSensitive(at_pointer(schema, pointers[p]), "properties");
        if (props == NULL)
            fprintf(stderr, "  schema has no properties at %s\n", pointers[p]);
        const cJSON *k;
        cJSON_ArrayForEach(k, props)
        {
            bool seen = false;
            for (int i = 0; i < n; i++)
                seen = seen || strcmp(keys[i], k->string) == 0;
            if (!seen && n < max)
                snprintf(keys[n++], 64, "%s", k->string);
        }
    }
    return n;
}

/* The keys after "allowed: " in the daemon's message. */
static int daemon_keys(const char *message, char keys[][64], int max)
{
    const char *p = strstr(message, "allowed: ");
    if (p == NULL)
        return -1;
    p += 9;
    int n = 0;
    while (*p && n < max) {
        size_t len = strcspn(p, ",");
        snprintf(keys[n++], 64, "%.*s", (int)len, p);
        p += len;
        while (*p == ',' || *p == ' ')
            p++;
    }
    return n;
}

static int compare_keys(const void *a, const void *b)
{
    return strcmp((const char *)a, (const char *)b);
}

static void same_keys(struct test_daemon *d, const cJSON *schema, const struct schema_case *c)
{
    char *body = NULL;
    long status = test_request(d, "POST", "/v1/scenes", c->document, &body);
    cJSON *root = cJSON_Parse(body ? body : "");
    const cJSON *msg = cJSON_GetObjectItemCaseSensitive(
        cJSON_GetObjectItemCaseSensitive(root, "error"), "message");
    char want[32][64], got[32][64];
    int nw = schema_keys(schema, c->pointers, want, 32);
    int ng = cJSON_IsString(msg) ? daemon_keys(msg->valuestring, got, 32) : -1;
    bool ok = status == 400 && ng == nw && nw > 0;
    qsort(want, (size_t)nw, sizeof want[0], compare_keys);
    if (ng > 0)
        qsort(got, (size_t)ng, sizeof got[0], compare_keys);
    for (int i = 0; ok && i < nw; i++)
        ok = strcmp(want[i], got[i]) == 0;
    CHECK_MSG(ok, "%s: schema and daemon disagree", c->where);
    if (!ok) {
        fprintf(stderr, "  HTTP %ld: %s\n  schema:", status, body ? body : "");
        for (int i = 0; i < nw; i++)
            fprintf(stderr, " %s", want[i]);
        fprintf(stderr, "\n");
    }
    cJSON_Delete(root);
    free(body);
}

int main(void)
{
    size_t len = 0;
    char *text = test_read_source_file("proto/scene.schema.json", &len);
    cJSON *schema = text ? cJSON_ParseWithLength(text, len) : NULL;
    free(text);
    if (schema == NULL)
        test_setup_failed("test_scene_schema", "proto/scene.schema.json is missing or not JSON");
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_scene_schema", d.why);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        same_keys(&d, schema, &cases[i]);
    printf("%zu levels of the scene document compared with proto/scene.schema.json\n",
           sizeof cases / sizeof cases[0]);
    cJSON_Delete(schema);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_scene_schema");
}
