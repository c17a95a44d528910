/* A tracer for twinray to judge, in plain C: spheres and triangle meshes, every ray against every primitive, in
 * double. Where a newcomer starts (docs/plugins.md): build it as a shared library and run
 * `twinray conform ./libbrute_force_tracer.so`. */
#include <twinray/tracer.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct { double x, y, z; } vec;
static vec load(const double* p) { vec v = {p[0], p[1], p[2]}; return v; }
static vec sub(vec a, vec b) { vec v = {a.x - b.x, a.y - b.y, a.z - b.z}; return v; }
static double dot(vec a, vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static vec cross(vec a, vec b) { vec v = {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; return v; }
static vec scaled(vec a, double s) { vec v = {a.x * s, a.y * s, a.z * s}; return v; }

typedef struct { vec a, b, c; uint32_t object, index; } triangle;
typedef struct {
    twinray_sphere* spheres; size_t sphere_count;
    triangle* triangles; size_t triangle_count;
} scene;

static void release(void* built) {
    scene* s = built;
    free(s->spheres);
    free(s->triangles);
    free(s);
}

static void* build(const twinray_scene* in, char* error, size_t error_size) {
    scene* s = calloc(1, sizeof *s);
    size_t m, t, k = 0;
    if (!s) { snprintf(error, error_size, "out of memory"); return NULL; }
    s->sphere_count = in->sphere_count;
    s->spheres = malloc(in->sphere_count * sizeof *s->spheres + 1);
    for (m = 0; m < in->mesh_count; ++m) s->triangle_count += in->meshes[m].triangle_count;
    s->triangles = malloc(s->triangle_count * sizeof *s->triangles + 1);
    if (!s->spheres || !s->triangles) { release(s); snprintf(error, error_size, "out of memory"); return NULL; }
    memcpy(s->spheres, in->spheres, in->sphere_count * sizeof *s->spheres);
    for (m = 0; m < in->mesh_count; ++m) {
        const twinray_mesh* mesh = &in->meshes[m];
        for (t = 0; t < mesh->triangle_count; ++t, ++k) {
            const uint32_t* corner = &mesh->triangles[3 * t];
            triangle tri = {load(&mesh->vertices[3 * corner[0]]), load(&mesh->vertices[3 * corner[1]]),
                            load(&mesh->vertices[3 * corner[2]]), mesh->object, (uint32_t)t};
            s->triangles[k] = tri;
        }
    }
    return s;
}

static void record(twinray_hit* hit, double t, vec normal, uint32_t object, uint32_t primitive, double u, double v,
                   int entering) {
    hit->hit = 1; hit->object = object; hit->primitive = primitive; hit->instance = TWINRAY_NONE; hit->t = t;
    hit->normal[0] = normal.x; hit->normal[1] = normal.y; hit->normal[2] = normal.z;
    hit->u = u; hit->v = v; hit->entering = (uint32_t)entering;
}

/* Calls visit for every crossing of the ray with t in (t_min, t_max): both roots of each sphere, then each
 * triangle met (Moller-Trumbore, a ray in a triangle's plane meets nothing). The sphere's discriminant is
 * r^2 - |f - (f.d) d|^2, not b^2 - c, and its nearer root c / q: neither cancels (Ray Tracing Gems, ch. 7). */
static void each_crossing(const scene* s, const twinray_ray* ray, void (*visit)(void*, const twinray_hit*), void* state) {
    vec o = load(ray->origin), d = load(ray->direction);
    twinray_hit hit;
    size_t i;
    for (i = 0; i < s->sphere_count; ++i) {
        const twinray_sphere* sphere = &s->spheres[i];
        vec centre = load(sphere->center), f = sub(o, centre);
        vec chord = sub(f, scaled(d, dot(f, d)));
        double b = dot(f, d), c = dot(f, f) - sphere->radius * sphere->radius, q, t;
        double disc = sphere->radius * sphere->radius - dot(chord, chord);
        int side;
        if (disc < 0) continue;
        q = -b - copysign(sqrt(disc), b);
        if (q == 0) continue;
        for (side = 0; side < 2; ++side) {
            t = (side == 0) == (q > 0) ? c / q : q;
            if (t <= ray->t_min || t >= ray->t_max) continue;
            record(&hit, t, scaled(sub(f, scaled(d, -t)), 1 / sphere->radius), sphere->object, TWINRAY_NONE,
                   0, 0, side == 0);
            visit(state, &hit);
        }
    }
    for (i = 0; i < s->triangle_count; ++i) {
        const triangle* tri = &s->triangles[i];
        vec e1 = sub(tri->b, tri->a), e2 = sub(tri->c, tri->a), p = cross(d, e2), q, n;
        double det = dot(e1, p), u, v, t;
        if (det == 0) continue;
        u = dot(sub(o, tri->a), p) / det;
        q = cross(sub(o, tri->a), e1);
        v = dot(d, q) / det;
        t = dot(e2, q) / det;
        if (u < 0 || v < 0 || u + v > 1 || t <= ray->t_min || t >= ray->t_max) continue;
        n = cross(e1, e2);
        record(&hit, t, scaled(n, 1 / sqrt(dot(n, n))), tri->object, tri->index, u, v, dot(n, d) < 0);
        visit(state, &hit);
    }
}

static void keep_nearest(void* state, const twinray_hit* hit) {
    twinray_hit* nearest = state;
    if (!nearest->hit || hit->t < nearest->t || (hit->t == nearest->t && hit->object < nearest->object)) *nearest = *hit;
}

static int intersect(void* built, const twinray_ray* rays, size_t count, twinray_hit* hits, size_t* written,
                     char* error, size_t error_size) {
    size_t i;
    (void)error; (void)error_size;
    for (i = 0; i < count; ++i) {
        hits[i].hit = 0;
        each_crossing(built, &rays[i], keep_nearest, &hits[i]);
    }
    *written = count;
    return 0;
}

typedef struct { twinray_hit* hits; size_t capacity, total; } collection;

/* Inserted in order of t as they come: segments cross few surfaces. */
static void collect(void* state, const twinray_hit* hit) {
    collection* c = state;
    size_t at = c->total < c->capacity ? c->total : c->capacity;
    while (at > 0 && c->hits[at - 1].t > hit->t) {
        if (at < c->capacity) c->hits[at] = c->hits[at - 1];
        --at;
    }
    if (at < c->capacity) c->hits[at] = *hit;
    ++c->total;
}

static int hits_along(void* built, const twinray_ray* ray, twinray_hit* hits, size_t capacity, size_t* total,
                      char* error, size_t error_size) {
    collection c = {hits, capacity, 0};
    (void)error; (void)error_size;
    each_crossing(built, ray, collect, &c);
    *total = c.total;
    return 0;
}

static const twinray_tracer tracer = {
    TWINRAY_TRACER_ABI_VERSION, TWINRAY_TRACER_THREAD_SAFE, "brute force (C example)", "1.0",
    TWINRAY_KIND_SPHERE | TWINRAY_KIND_TRIANGLES, 0x1p-53, build, intersect, hits_along, release};

const twinray_tracer* twinray_tracer_entry(void) { return &tracer; }
