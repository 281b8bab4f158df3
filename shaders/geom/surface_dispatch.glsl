// surface_dispatch.glsl - geom_surface_intersect and geom_surface_inside over the kinds
// (the twins of server/core/geom/surface.c), after the kinds' files.

bool geom_surface_intersect(int k, vec3 o_world, vec3 d_world, float tmin, float tmax,
                            int skip_prim, out geom_hit h)
{
    surface_params sp = surfaces[k];
    float scale = sp.medium.y;
    vec3 o = (sp.object_from_world * vec4(o_world, 1.0)).xyz;
    vec3 d = normalize(mat3(sp.object_from_world) * d_world);
    float t0 = tmin / scale, t1 = tmax / scale;
    bool hit = false;
    int kind = sp.kind.x;
    if (kind == GEOM_SPHERE)
        hit = sphere_intersect(sp.shape0.xyz, sp.shape0.w, o, d, t0, t1, h);
    else if (kind == GEOM_BOX)
        hit = box_intersect(sp.shape0.xyz, sp.shape1.xyz, o, d, t0, t1, h);
    else if (kind == GEOM_ROUNDED_BOX)
        hit = rounded_box_intersect(sp.shape0.xyz, sp.shape1.xyz, sp.shape0.w, o, d, t0, t1, h);
    else if (kind == GEOM_CYLINDER)
        hit = cylinder_intersect(sp.shape0.xyz, sp.shape0.w, sp.shape1.x, sp.kind.y, o, d, t0, t1,
                                 h);
    else if (kind == GEOM_PLANE)
        hit = plane_intersect(sp.shape0.xyz, sp.shape1.xyz, o, d, t0, t1, h);
    else if (kind == GEOM_LATHE)
        hit = lathe_intersect(sp.shape0.xyz, sp.kind.y, sp.kind.z, sp.kind.w, sp.shape0.w,
                              sp.shape1.xyz, o, d, t0, t1, h);
#if MARCH_MESHES
    else if (kind == GEOM_MESH) {
        float t;
        vec3 ng, ns;
        int tri;
        hit = mesh_rt_intersect(sp.mesh, o, d, t0, t1, skip_prim, t, ng, ns, tri);
        h.t = t;
        h.normal = ng;
        h.shading = ns;
        h.prim = tri;
    }
#endif
    else {
        h.t = 0.0;
        h.normal = vec3(0.0);
        h.shading = vec3(0.0);
        h.prim = 0;
    }
    if (!hit)
        return false;
    // Rotation only: world_from_object's 3x3 part is scale * R.
    mat3 rot = mat3(sp.world_from_object) / scale;
    h.t *= scale;
    h.normal = normalize(rot * h.normal);
    h.shading = normalize(rot * h.shading);
    return true;
}
