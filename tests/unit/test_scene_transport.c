/*
 * test_scene_transport.c - scene_transport_hash, the scene half of the irradiance cache
 * key: documents that describe the same transport (defaults written out or left away, keys
 * reordered, only lights, camera, environment, emission, anisotropy, BRDFs, names or other
 * render settings changed) hash equal, and a change to any transport-relevant field
 * changes the hash. Also scene_needs_light_simulation.
 */
#include <string.h>

#include "scene/scene.h"
#include "scene_test_util.h"
#include "test.h"

/* The base scene: glass sphere over a receiver, smoke in a second object. Cases are
 * written as whole documents so that each one is a spelling a client could send. */
#define GLASS                                                                                      \
    "{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 16, "               \
    "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.5, \"inside\": 1.5}}"
#define SMOKE                                                                                      \
    "{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8, "                \
    "\"scattering\": 0.3, \"transform\": {\"translate\": [2, 0, 0]}}"
#define BASE "{\"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", " SMOKE "]}"

static uint64_t hash_of(const char *doc, bool *ok)
{
    struct scene *s = parse_ok(doc);
    *ok = s != NULL;
    uint64_t h = s ? scene_transport_hash(s) : 0;
    scene_destroy(s);
    return h;
}

struct hash_case {
    const char *what;
    const char *doc;
};

/* clang-format off */
static const struct hash_case same_transport[] = {
    {"every default written out",
     "{\"name\": \"untitled\", \"ambient_ior\": 1, "
     "\"render\": {\"boundary_threshold\": 0.02}, "
     "\"lightsim\": {\"resolution\": 64, \"step\": 0.5, \"initial_patches\": 64, \"max_level\": 6, "
     "\"split\": 1, \"energy_threshold\": 1e-4, \"point_radius\": 0.01, \"deposit\": \"flux\", "
     "\"cull_flipped\": false, \"max_patches\": 262144}, "
     "\"receiver\": {\"height\": -2, \"half_size\": 4.5, \"albedo\": 0.8}, \"objects\": ["
     "{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": [16, 16, 16], "
     "\"smoothing_sigma\": 1, \"opaque_ior\": 1.5, "
     "\"transform\": {\"translate\": [0, 0, 0], \"scale\": 1}, "
     "\"ior\": [{\"shape\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 0.5, \"inside\": 1.5}]}, "
     "{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8, "
     "\"scattering\": [0.3, 0.3, 0.3], \"transform\": {\"translate\": [2, 0, 0], \"scale\": 1}}]}"},
    {"keys in another order",
     "{\"objects\": [{\"ior\": {\"inside\": 1.5, \"radius\": 0.5, \"shape\": \"sphere\"}, "
     "\"resolution\": 16, \"bounds\": {\"max\": [1, 1, 1], \"min\": [-1, -1, -1]}}, "
     "{\"transform\": {\"translate\": [2, 0, 0]}, \"scattering\": 0.3, \"resolution\": 8, "
     "\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}}], \"receiver\": {\"height\": -2}}"},
    {"-0 for 0",
     "{\"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", "
     "{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8, "
     "\"scattering\": 0.3, \"transform\": {\"translate\": [2, -0.0, -0]}}]}"},
    {"lights added",
     "{\"lights\": [{\"type\": \"directional\", \"direction\": [0, -1, 0]}, {\"name\": \"b\", "
     "\"type\": \"spot\", \"position\": [0, 3, 0], \"direction\": [0, -1, 0], \"color\": 2, "
     "\"intensity\": 5}], \"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"camera, environment, name, description",
     "{\"name\": \"other\", \"description\": \"d\", \"camera\": {\"eye\": [3, 1, 4], \"fov_y_deg\": 20, "
     "\"width\": 64, \"height\": 48}, \"environment\": {\"intensity\": 3, \"rotation_deg\": 90}, "
     "\"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"render settings other than boundary_threshold",
     "{\"render\": {\"stepper\": \"euler\", \"step\": 0.25, \"max_steps\": 100, \"exposure\": 2, "
     "\"tonemap\": \"filmic\"}, \"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"receiver albedo",
     "{\"receiver\": {\"height\": -2, \"albedo\": [0.1, 0.5, 0.9]}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"emission, anisotropy, brdf, object names",
     "{\"receiver\": {\"height\": -2}, \"objects\": ["
     "{\"name\": \"ball\", \"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 16, "
     "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.5, \"inside\": 1.5}, \"emission\": 2, "
     "\"brdf\": {\"type\": \"phong\", \"exponent\": 50}}, "
     "{\"name\": \"fog\", \"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8, "
     "\"scattering\": 0.3, \"anisotropy\": 0.7, \"brdf\": {\"type\": \"none\"}, "
     "\"transform\": {\"translate\": [2, 0, 0]}}]}"},
    {"a rotation by 0 degrees",
     "{\"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", "
     "{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8, "
     "\"scattering\": 0.3, \"transform\": {\"translate\": [2, 0, 0], \"rotate\": {\"axis\": [1, 0, 0], "
     "\"angle_deg\": 0}}}]}"},
};

static const struct hash_case other_transport[] = {
    {"ambient_ior", "{\"ambient_ior\": 1.33, \"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"boundary_threshold", "{\"render\": {\"boundary_threshold\": 0.05}, \"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"receiver height", "{\"receiver\": {\"height\": -1.5}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"receiver half_size", "{\"receiver\": {\"height\": -2, \"half_size\": 4}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"no receiver", "{\"objects\": [" GLASS ", " SMOKE "]}"},
    {"lightsim resolution", "{\"lightsim\": {\"resolution\": 32}, \"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"lightsim step", "{\"lightsim\": {\"step\": 0.25}, \"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"lightsim initial_patches", "{\"lightsim\": {\"initial_patches\": 32}, \"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"lightsim max_level", "{\"lightsim\": {\"max_level\": 5}, \"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"lightsim split", "{\"lightsim\": {\"split\": 2}, \"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"lightsim energy_threshold", "{\"lightsim\": {\"energy_threshold\": 0}, \"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"lightsim point_radius", "{\"lightsim\": {\"point_radius\": 0.02}, \"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"lightsim deposit", "{\"lightsim\": {\"deposit\": \"max\"}, \"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"lightsim cull_flipped", "{\"lightsim\": {\"cull_flipped\": true}, \"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"lightsim max_patches", "{\"lightsim\": {\"max_patches\": 1024}, \"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", " SMOKE "]}"},
    {"the glass's index",
     "{\"receiver\": {\"height\": -2}, \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
     "\"resolution\": 16, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.5, \"inside\": 1.51}}, " SMOKE "]}"},
    {"the glass's radius",
     "{\"receiver\": {\"height\": -2}, \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
     "\"resolution\": 16, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.4, \"inside\": 1.5}}, " SMOKE "]}"},
    {"a box instead of a sphere",
     "{\"receiver\": {\"height\": -2}, \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
     "\"resolution\": 16, \"ior\": {\"shape\": \"box\", \"size\": [0.5, 0.5, 0.5], \"inside\": 1.5}}, " SMOKE "]}"},
    {"an outside value",
     "{\"receiver\": {\"height\": -2}, \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
     "\"resolution\": 16, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.5, \"inside\": 1.5, \"outside\": 1}}, " SMOKE "]}"},
    {"object resolution",
     "{\"receiver\": {\"height\": -2}, \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
     "\"resolution\": [16, 16, 17], \"ior\": {\"shape\": \"sphere\", \"radius\": 0.5, \"inside\": 1.5}}, " SMOKE "]}"},
    {"object bounds",
     "{\"receiver\": {\"height\": -2}, \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1.1]}, "
     "\"resolution\": 16, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.5, \"inside\": 1.5}}, " SMOKE "]}"},
    {"smoothing_sigma",
     "{\"receiver\": {\"height\": -2}, \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
     "\"resolution\": 16, \"smoothing_sigma\": 0.5, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.5, \"inside\": 1.5}}, " SMOKE "]}"},
    {"opaque_ior",
     "{\"receiver\": {\"height\": -2}, \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
     "\"resolution\": 16, \"opaque_ior\": 1.6, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.5, \"inside\": 1.5}}, " SMOKE "]}"},
    {"an attenuation layer",
     "{\"receiver\": {\"height\": -2}, \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
     "\"resolution\": 16, \"attenuation\": 0.1, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.5, \"inside\": 1.5}}, " SMOKE "]}"},
    {"an opaque layer",
     "{\"receiver\": {\"height\": -2}, \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
     "\"resolution\": 16, \"opaque\": {\"shape\": \"sphere\", \"radius\": 0.1, \"inside\": 0.5}, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.5, \"inside\": 1.5}}, " SMOKE "]}"},
    {"scattering colour",
     "{\"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", "
     "{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8, "
     "\"scattering\": [0.3, 0.3, 0.31], \"transform\": {\"translate\": [2, 0, 0]}}]}"},
    {"the smoke's translation",
     "{\"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", "
     "{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8, "
     "\"scattering\": 0.3, \"transform\": {\"translate\": [2, 0.001, 0]}}]}"},
    {"the smoke's rotation",
     "{\"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", "
     "{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8, "
     "\"scattering\": 0.3, \"transform\": {\"translate\": [2, 0, 0], \"rotate\": {\"axis\": [0, 1, 0], \"angle_deg\": 10}}}]}"},
    {"the smoke's scale",
     "{\"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", "
     "{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8, "
     "\"scattering\": 0.3, \"transform\": {\"translate\": [2, 0, 0], \"scale\": 1.1}}]}"},
    {"the objects' order", "{\"receiver\": {\"height\": -2}, \"objects\": [" SMOKE ", " GLASS "]}"},
    {"one object fewer", "{\"receiver\": {\"height\": -2}, \"objects\": [" GLASS "]}"},
    {"a volume layer's name",
     "{\"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", "
     "{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8, "
     "\"scattering\": {\"volume\": \"smoke\"}, \"transform\": {\"translate\": [2, 0, 0]}}]}"},
    {"a volume layer's scale",
     "{\"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", "
     "{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8, "
     "\"scattering\": {\"volume\": \"smoke\", \"scale\": 2}, \"transform\": {\"translate\": [2, 0, 0]}}]}"},
    {"a volume layer's offset",
     "{\"receiver\": {\"height\": -2}, \"objects\": [" GLASS ", "
     "{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8, "
     "\"scattering\": {\"volume\": \"smoke\", \"offset\": 0.1}, \"transform\": {\"translate\": [2, 0, 0]}}]}"},
    {"a GRIN profile",
     "{\"receiver\": {\"height\": -2}, \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
     "\"resolution\": 16, \"ior\": {\"profile\": \"luneburg\", \"radius\": 0.5}}, " SMOKE "]}"},
    {"a GRIN profile's radius",
     "{\"receiver\": {\"height\": -2}, \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
     "\"resolution\": 16, \"ior\": {\"profile\": \"luneburg\", \"radius\": 0.6}}, " SMOKE "]}"},
    {"a lathe",
     "{\"receiver\": {\"height\": -2}, \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
     "\"resolution\": 16, \"ior\": {\"shape\": \"lathe\", \"profile\": [[0, 0], [0.5, 0], [0.5, 0.5], [0, 0.5]], \"inside\": 1.5}}, " SMOKE "]}"},
    {"a lathe's point",
     "{\"receiver\": {\"height\": -2}, \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
     "\"resolution\": 16, \"ior\": {\"shape\": \"lathe\", \"profile\": [[0, 0], [0.5, 0], [0.5, 0.6], [0, 0.5]], \"inside\": 1.5}}, " SMOKE "]}"},
    {"a text shape's string",
     "{\"receiver\": {\"height\": -2}, \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
     "\"resolution\": 16, \"ior\": {\"shape\": \"text\", \"text\": \"AB\", \"height\": 0.3, \"depth\": 0.2, \"inside\": 1.5}}, " SMOKE "]}"},
    {"bumpy_sphere frequency",
     "{\"receiver\": {\"height\": -2}, \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
     "\"resolution\": 16, \"ior\": {\"shape\": \"bumpy_sphere\", \"radius\": 0.5, \"bump_frequency\": 5, \"inside\": 1.5}}, " SMOKE "]}"},
};
/* clang-format on */

static void same_transport_gives_the_same_hash(void)
{
    bool ok;
    uint64_t base = hash_of(BASE, &ok);
    CHECK(ok);
    for (size_t i = 0; i < sizeof same_transport / sizeof same_transport[0]; i++) {
        uint64_t h = hash_of(same_transport[i].doc, &ok);
        CHECK_MSG(ok && h == base, "%s: %016llx != %016llx", same_transport[i].what,
                  (unsigned long long)h, (unsigned long long)base);
    }
}

static void other_transport_gives_another_hash(void)
{
    enum { N = sizeof other_transport / sizeof other_transport[0] };
    bool ok;
    uint64_t hashes[N + 1];
    hashes[N] = hash_of(BASE, &ok);
    for (size_t i = 0; i < N; i++) {
        hashes[i] = hash_of(other_transport[i].doc, &ok);
        CHECK_MSG(ok && hashes[i] != hashes[N], "%s: hash unchanged", other_transport[i].what);
    }
    /* And all of them differ from each other: no two changes collide. */
    size_t collisions = 0;
    for (size_t i = 0; i < N; i++) {
        for (size_t j = i + 1; j < N; j++)
            collisions += hashes[i] == hashes[j];
    }
    CHECK_INT(collisions, 0);
}

/* A bumpy sphere with amplitude 0 is a different shape (kind) from a sphere, and the same
 * bumpy sphere with its default amplitude spelled out is the same. */
static void bumpy_sphere_defaults_hash_like_their_spelling(void)
{
    bool ok1, ok2;
    uint64_t a = hash_of("{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
                         "\"ior\": {\"shape\": \"bumpy_sphere\", \"radius\": 0.5, \"inside\": "
                         "1.5}}]}",
                         &ok1);
    uint64_t b = hash_of("{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
                         "\"ior\": {\"shape\": \"bumpy_sphere\", \"radius\": 0.5, "
                         "\"bump_amplitude\": 0.05, \"bump_frequency\": 6, \"inside\": 1.5}}]}",
                         &ok2);
    CHECK(ok1 && ok2 && a == b);
}

/* The hash depends on the values in the structs, not on where they live: a scene copied
 * field by field hashes equal, and dropping one layer from the copy changes it. */
static void hash_reads_the_structs_not_their_addresses(void)
{
    struct scene *s = parse_ok(BASE);
    if (s == NULL)
        return;
    uint64_t h = scene_transport_hash(s);
    CHECK(h == scene_transport_hash(s));
    struct scene copy = *s;
    struct scene_object objs[2];
    memcpy(objs, s->objects, sizeof objs);
    copy.objects = objs;
    CHECK(scene_transport_hash(&copy) == h);
    objs[1].fields[SCENE_CH_SCATTERING].layers = NULL; /* make the copy differ */
    objs[1].fields[SCENE_CH_SCATTERING].count = 0;
    CHECK(scene_transport_hash(&copy) != h);
    scene_destroy(s);
}

static void needs_light_simulation_for_scattering_or_a_receiver(void)
{
    static const struct {
        const char *doc;
        bool needs;
    } cases[] = {
        {"{\"objects\": [" GLASS "]}", false},
        {"{\"lights\": [{\"type\": \"directional\", \"direction\": [0, -1, 0]}], \"objects\": "
         "[" GLASS "]}",
         false},
        {"{\"receiver\": {\"height\": -2}, \"objects\": [" GLASS "]}", true},
        {"{\"objects\": [" GLASS ", " SMOKE "]}", true},
        {"{\"objects\": [{\"bounds\": {\"min\": [0, 0, 0], \"max\": [1, 1, 1]}, \"ior\": 1.2, "
         "\"scattering\": {\"shape\": \"box\", \"size\": [0.1, 0.1, 0.1], \"inside\": 0}}]}",
         true},
        /* a surface's constant medium that scatters (docs/tracing.md "Scattering inside
         * surfaces"); one that only absorbs does not; a lone scattering sphere gets exact
         * single scattering instead (docs/walter.md "When") */
        {"{\"surfaces\": [{\"shape\": \"box\", \"size\": [1, 1, 1], \"medium\": {\"ior\": 1.5, "
         "\"scattering\": [0, 0.5, 0]}}]}",
         true},
        {"{\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": {\"ior\": 1.5, "
         "\"scattering\": [0, 0.5, 0]}}]}",
         false},
        {"{\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": {\"ior\": 1.5, "
         "\"scattering\": [0, 0.5, 0]}}, {\"shape\": \"sphere\", \"center\": [3, 0, 0], "
         "\"radius\": 1, \"medium\": {\"ior\": 1.5}}]}",
         true},
        {"{\"receiver\": {\"height\": -2, \"caustics\": \"photons\"}, \"surfaces\": [{\"shape\": "
         "\"sphere\", \"radius\": 1, \"medium\": {\"ior\": 1.5}}]}",
         false},
        {"{\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": {\"ior\": 1.5, "
         "\"attenuation\": [1, 1, 1], \"anisotropy\": 0.5}}]}",
         false},
        {"{\"objects\": [{\"bounds\": {\"min\": [0, 0, 0], \"max\": [1, 1, 1]}, \"attenuation\": "
         "1, "
         "\"emission\": 1, \"opaque\": 1}]}",
         false},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        struct scene *s = parse_ok(cases[i].doc);
        if (s == NULL)
            continue;
        CHECK_MSG(scene_needs_light_simulation(s) == cases[i].needs, "%s: expected %s",
                  cases[i].doc, cases[i].needs ? "true" : "false");
        scene_destroy(s);
    }
}

/* A surface medium's scattering is part of the light simulator's extinction: it changes
 * the hash; zero scattering and the anisotropy (render time only) do not. */
static void surface_scattering_changes_the_hash(void)
{
#define SURF(m)                                                                                    \
    "{\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": {\"ior\": 1.5" m "}}]}"
    bool ok[4];
    uint64_t plain = hash_of(SURF(""), &ok[0]);
    uint64_t zero = hash_of(SURF(", \"scattering\": [0, 0, 0], \"anisotropy\": 0.3"), &ok[1]);
    uint64_t a = hash_of(SURF(", \"scattering\": [0.5, 0.5, 0.5]"), &ok[2]);
    uint64_t b = hash_of(SURF(", \"scattering\": [0.5, 0.5, 0.6], \"anisotropy\": 0.3"), &ok[3]);
#undef SURF
    CHECK(ok[0] && ok[1] && ok[2] && ok[3]);
    CHECK(plain == zero);
    CHECK(a != plain);
    CHECK(a != b);
}

int main(void)
{
    same_transport_gives_the_same_hash();
    other_transport_gives_another_hash();
    bumpy_sphere_defaults_hash_like_their_spelling();
    hash_reads_the_structs_not_their_addresses();
    needs_light_simulation_for_scattering_or_a_receiver();
    surface_scattering_changes_the_hash();
    return test_summary("test_scene_transport");
}
