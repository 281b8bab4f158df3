// kinds.glsl - every exact surface kind's file (the twins of server/core/geom/*.c), then the
// dispatch over them: what a march includes to see surfaces. A new kind adds its file here.
#include "geom/geom_hit.glsl"
#include "geom/surface.glsl"
#include "geom/sphere.glsl"
#include "geom/box.glsl"
#include "geom/rounded_box.glsl"
#include "geom/cylinder.glsl"
#include "geom/plane.glsl"
#include "geom/lathe.glsl"
#if MARCH_MESHES
#include "geom/mesh.glsl"
#endif
#include "geom/surface_dispatch.glsl"
