/* twinray's tracer ABI, version 1: how a ray tracer of anyone's is put where twinray's own SSE tracer stands, to
 * be judged ray by ray against the double-precision oracle (docs/plugins.md).
 *
 * A tracer is a shared library exporting one C function, TWINRAY_TRACER_ENTRY_NAME, that returns its table of
 * functions. twinray gives it a scene as flat arrays in double, world coordinates, and asks it for the nearest
 * hit of batches of rays and for every hit along a segment; shading, shadows, reflection, refraction and depth
 * control stay twinray's, so that a difference in an image belongs to the intersector alone.
 *
 * C99; nothing of C++ crosses it.
 *
 * Ownership: everything twinray passes (the scene's arrays, the rays, the hit buffers, error buffers) is
 * twinray's and valid only during the call: a tracer copies what it keeps. What `build` returns is the
 * tracer's until twinray hands it to `release`, exactly once. The strings of the table are the tracer's and
 * must live as long as the library is loaded.
 *
 * Alignment: arrays are aligned as their C types are (8 bytes for double), no more; a tracer that wants 16 or 64
 * copies.
 *
 * Threading: `build` and `release` are called from one thread at a time. `intersect` and `hits_along` on one
 * built scene are called from several threads at once only where the table's flags hold
 * TWINRAY_TRACER_THREAD_SAFE; otherwise from one thread at a time.
 *
 * Errors: a function that fails returns a non-zero status (or NULL from `build`) and writes a message of at most
 * `error_size` bytes, NUL included, into `error`. twinray reports it with the tracer's name and exits with its
 * status for a failed plug-in. A tracer must not abort the process; twinray's `conform` runs it in a child
 * process all the same, so that one that crashes or hangs is reported, not fatal.
 *
 * Numbers: rays and hits are in double. A tracer rounds them as it likes and states its unit roundoff
 * (2^-24 for float, 2^-53 for double): twinray holds its hits to the tolerance that precision earns.
 */
#ifndef TWINRAY_TRACER_H
#define TWINRAY_TRACER_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The version this header describes. A later version keeps the first member of twinray_tracer where it is. */
#define TWINRAY_TRACER_ABI_VERSION 1u
#define TWINRAY_TRACER_ENTRY_NAME "twinray_tracer_entry"

/* An index that names nothing: a primitive without a transform, a hit on something that is not a triangle, a hit
 * outside every instance. */
#define TWINRAY_NONE 0xFFFFFFFFu

/* The kinds of primitive a tracer intersects (twinray_tracer.kinds). A scene holding a kind the tracer lacks is
 * refused before `build`, naming the kind. */
#define TWINRAY_KIND_PLANE 0x01u
#define TWINRAY_KIND_SPHERE 0x02u
#define TWINRAY_KIND_CYLINDER 0x04u
#define TWINRAY_KIND_BOX 0x08u
#define TWINRAY_KIND_TRIANGLES 0x10u
/* Spheres, cylinders and boxes placed by a transform no primitive of their kind can express (an ellipsoid, a
 * box turned off the axes): their `transform` is not TWINRAY_NONE. */
#define TWINRAY_KIND_TRANSFORMED 0x20u
/* Triangle meshes declared once as shapes and placed by instances. */
#define TWINRAY_KIND_INSTANCES 0x40u
/* Version 1 carries no CSG: a scene with CSG is refused for every plug-in. */

/* twinray_tracer.flags */
#define TWINRAY_TRACER_THREAD_SAFE 0x01u

/* Object space to world: p -> linear * p + translation, `linear` row-major, invertible and well conditioned
 * (twinray's loader refuses a condition number above 1e5). */
typedef struct twinray_transform {
    double linear[3][3];
    double translation[3];
} twinray_transform;

/* Every primitive names its `object`: the number twinray gives each leaf of the scene, which a hit returns.
 * `transform`, where a kind has one, indexes twinray_scene.transforms or is TWINRAY_NONE; the primitive's own
 * numbers are then in its object space. */

/* The surface dot(normal, p) = offset, `normal` of unit length; the inside is dot(normal, p) < offset. */
typedef struct twinray_plane {
    double normal[3];
    double offset;
    uint32_t object;
} twinray_plane;

typedef struct twinray_sphere {
    double center[3];
    double radius;
    uint32_t object;
    uint32_t transform;
} twinray_sphere;

/* Solid and closed: flat caps at `base` and `cap`. */
typedef struct twinray_cylinder {
    double base[3];
    double cap[3];
    double radius;
    uint32_t object;
    uint32_t transform;
} twinray_cylinder;

/* Axis-aligned in its own space: min < max on every axis. */
typedef struct twinray_box {
    double min[3];
    double max[3];
    uint32_t object;
    uint32_t transform;
} twinray_box;

/* `vertices`: x, y, z of each vertex; `triangles`: three vertex indices each, counter-clockwise seen from the
 * front. A mesh is a surface, not a solid: a ray enters where it meets a front, leaves where it meets a back.
 * Degenerate triangles (a repeated index, collinear vertices) are kept so that indices are the file's; a hit
 * on one is wrong. In twinray_scene.meshes the vertices are world coordinates and `object` the mesh's; in
 * twinray_scene.shapes they are the shape's own space and `object` is TWINRAY_NONE. */
typedef struct twinray_mesh {
    const double* vertices;
    uint32_t vertex_count;
    const uint32_t* triangles;
    uint32_t triangle_count;
    uint32_t object;
} twinray_mesh;

/* One placement of shapes[shape]; a hit on it names this `object`. A mirroring transform (negative determinant)
 * turns the triangles' fronts. */
typedef struct twinray_instance {
    uint32_t shape;
    uint32_t object;
    twinray_transform to_world;
} twinray_instance;

typedef struct twinray_scene {
    const twinray_plane* planes;
    uint32_t plane_count;
    const twinray_sphere* spheres;
    uint32_t sphere_count;
    const twinray_cylinder* cylinders;
    uint32_t cylinder_count;
    const twinray_box* boxes;
    uint32_t box_count;
    const twinray_mesh* meshes;
    uint32_t mesh_count;
    const twinray_mesh* shapes;
    uint32_t shape_count;
    const twinray_instance* instances;
    uint32_t instance_count;
    const twinray_transform* transforms;
    uint32_t transform_count;
    /* Every `object` above is below this. Where two surfaces meet a ray at the same t, the smaller object wins. */
    uint32_t object_count;
    /* Where most rays start, the camera's eye in world coordinates: a hint a float tracer may compile its scene
     * relative to, as twinray's SSE tracer does (docs/numerics.md, "Far from the origin: re-basing"), so that a
     * scene far from the origin keeps float's precision near the camera. It bounds nothing: rays may start
     * anywhere. */
    double eye[3];
} twinray_scene;

/* The segment origin + t * direction, t_min < t < t_max; `direction` of unit length; t_max may be +infinity. */
typedef struct twinray_ray {
    double origin[3];
    double direction[3];
    double t_min;
    double t_max;
} twinray_ray;

typedef struct twinray_hit {
    uint32_t hit; /* 1: a hit, the members below filled; 0: a miss, the rest ignored */
    uint32_t object;
    uint32_t primitive; /* the triangle's index in its mesh or shape; TWINRAY_NONE on any other primitive */
    uint32_t instance;  /* the index in twinray_scene.instances; TWINRAY_NONE outside every instance */
    double t;
    /* Unit, world space, the surface's outward normal (a triangle's front), whichever side the ray comes from. */
    double normal[3];
    /* On a triangle a, b, c: the hit point is (1 - u - v) a + u b + v c. 0 on any other primitive. */
    double u, v;
    uint32_t entering; /* 1 where the ray enters the solid or meets a triangle's front, 0 where it leaves */
} twinray_hit;

typedef struct twinray_tracer {
    uint32_t abi_version; /* TWINRAY_TRACER_ABI_VERSION as the tracer was built */
    uint32_t flags;       /* TWINRAY_TRACER_THREAD_SAFE or 0 */
    const char* name;
    const char* version;
    uint32_t kinds;       /* TWINRAY_KIND_* it intersects */
    double unit_roundoff; /* of the arithmetic its hits are found in: 2^-24 for float, 2^-53 for double */

    /* Builds the tracer's own structure for `scene`: NULL and a message on failure. */
    void* (*build)(const twinray_scene* scene, char* error, size_t error_size);

    /* The nearest hit of each of `count` rays into `hits[i]`, `*written` set to how many were written (count).
     * Ties in t go to the smaller object. */
    int (*intersect)(void* built, const twinray_ray* rays, size_t count, twinray_hit* hits, size_t* written,
                     char* error, size_t error_size);

    /* Every hit along one segment, by increasing t: the first `capacity` into `hits`, their total into `*total`
     * (twinray asks again with room for them all where it is larger). A surface met twice at one t (a ray
     * through a shared edge) is two hits. */
    int (*hits_along)(void* built, const twinray_ray* ray, twinray_hit* hits, size_t capacity, size_t* total,
                      char* error, size_t error_size);

    void (*release)(void* built);
} twinray_tracer;

/* What the library exports under TWINRAY_TRACER_ENTRY_NAME. */
typedef const twinray_tracer* (*twinray_tracer_entry_function)(void);

#ifdef __cplusplus
}
#endif

#endif
