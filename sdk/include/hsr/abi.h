/*
 * hsr plugin ABI: the contract between the `hsr` host and its plugins.
 *
 * Pure C99. Nothing in this file may depend on C++: a test compiles it with a C compiler.
 * docs/abi.md explains the rules; the short form, in MUST / MUST NOT language:
 *
 *  - A plugin library exports exactly one symbol, HSR_ENTRY_SYMBOL ("hsr_plugin_entry"), of type
 *    hsr_entry_fn. The host calls it with index 0, 1, 2, ... until it returns NULL; each non-NULL
 *    result describes one plugin the library holds.
 *  - The first five fields of hsr_plugin_descriptor (struct_size, api, abi_major, abi_minor, kind) are
 *    frozen for ever, so any host can read them from any plugin. The host MUST refuse a plugin whose
 *    api is not HSR_API_NAME or whose abi_major differs from its own, and MUST refuse one whose
 *    abi_minor is newer than its own. It accepts an older minor and reads only the fields that the
 *    struct_size of each struct covers; fields beyond it are treated as absent (NULL / zero).
 *  - Every struct the host passes to a plugin starts with struct_size as well; a newer host passes
 *    larger structs, and a plugin MUST NOT read beyond the struct_size it was built with.
 *  - Arrays of structs (parameter descriptions and values, lights) are stepped by the struct_size of
 *    their elements, not by sizeof, so that their elements too can grow in a minor version: use
 *    HSR_ELEMENT(type, array, i). Every element of one array has the same struct_size.
 *  - Nothing C++ crosses: no exceptions (a plugin catches everything and returns a status), no RTTI,
 *    no STL types, no memory allocated on one side and freed on the other. Strings handed across are
 *    NUL-terminated UTF-8 and stay owned by the side that made them.
 *  - Every struct field has a fixed size: fields holding one of the enums below are uint32_t (C
 *    leaves an enum's size to the compiler); the enums name their values. Static assertions at the
 *    end of this file pin the frozen descriptor prefix.
 *  - Errors come back as an hsr_status; on failure the callee writes a one-line message into the
 *    caller's hsr_error buffer.
 *  - The host MUST NOT unload a library while any instance created from it is alive, and MUST NOT
 *    call into an instance after destroy().
 *  - Nothing crosses the boundary per pixel: a hidden-surface remover fills a whole visibility buffer
 *    in one call; a lighting model shades fragments in batches (one call per batch of up to
 *    hsr_fragment_batch.count fragments).
 *
 * Version history (append-only within a major):
 *   1.0  initial: descriptors with parameter schemas, IHiddenSurfaceRemover, ILightingModel,
 *        visibility buffer, fragment batches, counters, extension hooks.
 *   1.1  instancing: hsr_instance, hsr_scene.instance_count/instances, the per-pixel instance id in
 *        hsr_visibility_buffer and hsr_fragment_batch; hsr_visibility_buffer.depth_tests (per-pixel
 *        work counts for overdraw pictures). A host hands a 1.0 plugin an instanced scene only
 *        after copying the instances out into plain triangles.
 *   1.2  hidden-line removal: the plugin kind HSR_KIND_HIDDEN_LINE_REMOVER and its table
 *        IHiddenLineRemover; the edges to draw (hsr_line_request), the visible and hidden pieces
 *        that come back in batches (hsr_segment_batch, hsr_segment_sink) and the optional step
 *        events for replaying an algorithm (hsr_trace_event, hsr_trace_sink).
 *   1.3  hidden-surface removal step by step: IHiddenSurfaceRemover.render_steps, which reports each
 *        step of the algorithm (hsr_step_event: what it did, the lines to draw over the picture,
 *        the plugin's own buffers) to an hsr_step_sink that can stop the render after any step.
 *        Optional: a plugin without it renders as before, without steps.
 *   1.4  sections: hsr_camera.clip_plane_count and clip_planes, half-spaces that keep part of the
 *        scene. A host hands clip planes only to a plugin of minor 4 or later, which honours them or
 *        refuses the call with HSR_ERROR_UNSUPPORTED. Transparency and anti-aliasing:
 *        hsr_scene.object_opacity, and IHiddenSurfaceRemover.render_fragments (optional), which
 *        hands the host every pixel's list of surface fragments with their coverage of the pixel
 *        (hsr_pixel_fragments, hsr_fragment_sink) for it to shade and composite.
 *   1.5  phases and languages, for teaching: hsr_plugin_descriptor.phases lists the phases of an
 *        algorithm (hsr_phase_desc); hsr_step_event.phase and hsr_trace_event.phase name the phase a
 *        step belongs to, so that a viewer can highlight the line of pseudocode it executes.
 *        hsr_step_sink.language and hsr_trace_sink.language ask for step texts in a language.
 *        Optional: a plugin without phases steps as before.
 *   1.6  the plugin's own words in other languages: hsr_plugin_descriptor.translations
 *        (hsr_translation) gives its description, parameter names and help, choice names, phase
 *        titles, counter names and buffer names in, say, Russian, for a viewer in that language.
 *        Optional: what a plugin does not translate is shown in English.
 */
#ifndef HSR_ABI_H
#define HSR_ABI_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HSR_API_NAME "hsr"
#define HSR_ABI_MAJOR 1
#define HSR_ABI_MINOR 6
#define HSR_ENTRY_SYMBOL "hsr_plugin_entry"

#if defined(_WIN32)
#define HSR_EXPORT __declspec(dllexport)
#else
#define HSR_EXPORT __attribute__((visibility("default")))
#endif

/* Element i of an array of structs that begin with struct_size (see the rule above). */
#define HSR_ELEMENT(type, array, i) \
    ((const type*)((const char*)(array) + (size_t)(i) * ((const type*)(array))->struct_size))

/* ---------------------------------------------------------------------------------------------- */
/* Status codes and error messages                                                                 */

typedef enum hsr_status {
    HSR_OK = 0,
    HSR_ERROR_INVALID_ARGUMENT = 1, /* bad parameter value, bad scene for this algorithm, ... */
    HSR_ERROR_UNSUPPORTED = 2,      /* the plugin cannot do what was asked (e.g. a camera type) */
    HSR_ERROR_OUT_OF_MEMORY = 3,
    HSR_ERROR_INTERNAL = 4          /* anything else, including a C++ exception caught at the edge */
} hsr_status;

#define HSR_ERROR_MESSAGE_SIZE 512

/* Caller-owned buffer for a one-line, NUL-terminated error message. The callee writes it only when
 * it returns a status other than HSR_OK. */
typedef struct hsr_error {
    char message[HSR_ERROR_MESSAGE_SIZE];
} hsr_error;

/* ---------------------------------------------------------------------------------------------- */
/* Parameters                                                                                      */

typedef enum hsr_param_type {
    HSR_PARAM_BOOL = 0,  /* value.number is 0 or 1; text form "true|false|1|0|yes|no|on|off" */
    HSR_PARAM_INT = 1,   /* value.number holds an integer within [min, max]                 */
    HSR_PARAM_FLOAT = 2, /* value.number within [min, max]                                  */
    HSR_PARAM_ENUM = 3,  /* value.number is the index into choices; text form is the name   */
    HSR_PARAM_COLOR = 4  /* value.color, each channel in [0, 1]; text form "r/g/b" or "#rrggbb" */
} hsr_param_type;

/* One entry of a plugin's parameter schema. The host lists, validates and documents parameters from
 * this alone. All strings are static in the plugin library. The array is stepped by struct_size. */
typedef struct hsr_param_desc {
    uint32_t struct_size;
    const char* name;          /* lower-case, words joined by '-', e.g. "depth-test" */
    uint32_t type;             /* an hsr_param_type */
    const char* default_value; /* text form, parsed by the host like a user's value */
    double min;                /* INT and FLOAT: inclusive range */
    double max;
    const char* choices;       /* ENUM: names separated by '|', e.g. "less|greater"; else NULL */
    const char* help;          /* one line */
} hsr_param_desc;

/* A validated parameter value, as the host hands it to create(). The host always passes every
 * parameter of the schema, in schema order, defaults filled in. */
typedef struct hsr_param_value {
    uint32_t struct_size;
    const char* name;
    uint32_t type;  /* an hsr_param_type */
    double number;  /* BOOL, INT, FLOAT, ENUM (choice index) */
    float color[3]; /* COLOR */
} hsr_param_value;

/* ---------------------------------------------------------------------------------------------- */
/* Scene, camera, lights: read-only input, owned by the host, valid for the duration of a call.    */

#define HSR_NO_NEIGHBOR (-1)

/* Since 1.1: one placement of a range of the scene's triangles (usually one object) in the world.
 * The same triangles may be placed any number of times without being copied. The transform is a
 * similarity (rotation, positive uniform scale, translation: no mirroring or shear), so triangles
 * keep their winding, and a normal n maps to the unit vector rotation * n. */
typedef struct hsr_instance {
    uint32_t struct_size;
    uint32_t first_triangle;   /* the triangles [first_triangle, first_triangle + triangle_count) */
    uint32_t triangle_count;
    uint32_t first_vertex;     /* every vertex those triangles use lies in */
    uint32_t vertex_count;     /* [first_vertex, first_vertex + vertex_count) */
    float transform[16];       /* column-major, world = transform * (position, 1) */
    float rotation[9];         /* column-major 3x3: the transform's rotation, scale divided out */
    float scale;               /* the transform's uniform scale, > 0 */
    float bounds_min[3];       /* world-space bounds of the placed triangles */
    float bounds_max[3];
} hsr_instance;

/* All geometry of the scene as one indexed triangle mesh in world space. Several objects are
 * concatenated; face_object tells which object a triangle came from. Triangle t has corners
 * indices[3t+0..2], counter-clockwise seen from its front. */
typedef struct hsr_scene {
    uint32_t struct_size;
    uint32_t vertex_count;
    uint32_t triangle_count;
    uint32_t object_count;
    const float* positions;      /* 3 * vertex_count: x, y, z */
    const uint32_t* indices;     /* 3 * triangle_count */
    const float* face_normals;   /* 3 * triangle_count, unit length, pointing out of the front */
    const float* corner_normals; /* 9 * triangle_count: the shading normal at each corner (unit);
                                    shared across smooth edges, split at creases */
    const float* face_colors;    /* 3 * triangle_count, RGB in [0, 1] */
    const int32_t* edge_neighbors; /* 3 * triangle_count: for edge i of triangle t, running from
                                      corner i to corner (i+1)%3, the triangle across it, or
                                      HSR_NO_NEIGHBOR on a boundary (from the half-edge mesh) */
    const uint32_t* face_object; /* triangle_count: object index in [0, object_count) */
    float bounds_min[3];         /* axis-aligned world-space bounds of everything drawn */
    float bounds_max[3];
    /* Since 1.1: when instance_count > 0, positions and normals above are in object space and
     * what is drawn is exactly the instances: each instance's triangle range, transformed by it
     * (triangles no instance names are not drawn). A pixel then shows a (face, instance) pair.
     * When instance_count == 0 the mesh is in world space and drawn once, as in 1.0. */
    uint32_t instance_count;
    const hsr_instance* instances; /* instance_count elements, stepped by struct_size */
    /* Since 1.4: object_count opacities in [0, 1] (1: opaque, 0: invisible), or NULL: everything is
     * opaque. A host hands a scene with an opacity below 1 only to a remover with render_fragments. */
    const float* object_opacity;
} hsr_scene;

#define HSR_MAX_CLIP_PLANES 8

typedef enum hsr_projection {
    HSR_PROJECTION_PERSPECTIVE = 0,
    HSR_PROJECTION_ORTHOGRAPHIC = 1
} hsr_projection;

/* Matrices are column-major (as GLM and OpenGL), acting on column vectors: clip = projection * view
 * * world. Clip space follows OpenGL: visible points satisfy -w <= x, y, z <= w and w > 0. Window
 * coordinates: x_win = (x_ndc + 1) / 2 * width, y_win = (1 - y_ndc) / 2 * height (row 0 is the top
 * row of the image), depth = (z_ndc + 1) / 2, smaller is nearer. Pixel (px, py) has its centre at
 * (px + 0.5, py + 0.5). */
typedef struct hsr_camera {
    uint32_t struct_size;
    uint32_t width;  /* image size in pixels, equal to the visibility buffer's */
    uint32_t height;
    uint32_t projection_type; /* an hsr_projection */
    float view[16];
    float projection[16];
    float view_projection[16]; /* projection * view */
    float eye[3];              /* world-space eye point (perspective) */
    float view_direction[3];   /* world-space unit direction the camera looks along */
    float near_plane;          /* view-space distances of the clip planes */
    float far_plane;
    /* Since 1.4: sections. Only what lies on the kept side of every one of these world-space planes
     * is drawn: a point p is kept where a*p.x + b*p.y + c*p.z + d >= 0 for each plane (a, b, c, d).
     * What a plane cuts away hides nothing. Planes after clip_plane_count are zero. */
    uint32_t clip_plane_count; /* 0 .. HSR_MAX_CLIP_PLANES */
    float clip_planes[HSR_MAX_CLIP_PLANES][4];
} hsr_camera;

typedef enum hsr_light_type {
    HSR_LIGHT_POINT = 0,
    HSR_LIGHT_DIRECTIONAL = 1
} hsr_light_type;

typedef struct hsr_light {
    uint32_t struct_size;
    uint32_t type;    /* an hsr_light_type */
    float vector[3];  /* POINT: world-space position. DIRECTIONAL: unit world-space direction from
                         the surface toward the light. */
    float color[3];   /* RGB in [0, 1] */
    float intensity;  /* scales color */
} hsr_light;

/* ---------------------------------------------------------------------------------------------- */
/* Counters: what an algorithm did, reported as (name, value) pairs after a render.                */

/* The host provides the sink; a plugin calls report() once per counter at the end of a call
 * (never per pixel). Names are lower-case words joined by '-', e.g. "pixels-depth-tested". */
typedef struct hsr_counter_sink {
    void* context;
    void (*report)(void* context, const char* name, uint64_t value);
} hsr_counter_sink;

/* ---------------------------------------------------------------------------------------------- */
/* Hidden-surface removal                                                                          */

#define HSR_NO_FACE 0xFFFFFFFFu

/* Output of a hidden-surface remover: for every pixel, the visible triangle, its depth and the
 * perspective-correct barycentric coordinates (b1, b2) of the pixel centre on that triangle (the
 * weight of corner 0 is 1 - b1 - b2). Row-major, row 0 at the top. The host allocates the arrays
 * and clears them (face = HSR_NO_FACE, depth = +infinity, bary = 0) before render(). */
typedef struct hsr_visibility_buffer {
    uint32_t struct_size;
    uint32_t width;
    uint32_t height;
    float* depth;   /* width * height */
    uint32_t* face; /* width * height */
    float* bary;    /* 2 * width * height: b1, b2 interleaved */
    /* Since 1.1: */
    uint32_t* instance;    /* width * height: the instance of the visible face; non-NULL exactly
                              when the scene has instances (cleared to 0) */
    uint32_t* depth_tests; /* width * height or NULL: when non-NULL (cleared to 0), the plugin
                              adds 1 at a pixel for every depth comparison it makes there, so the
                              host can draw where the algorithm worked (overdraw) */
} hsr_visibility_buffer;

/* Since 1.3: the steps of a hidden-surface algorithm, for a viewer that replays them. */

/* Since 1.5: a phase of an algorithm (hsr_plugin_descriptor.phases): a part of it that the
 * algorithm's pseudocode writes as one line or block, such as "depth-test". Every step names the
 * phase it belongs to (hsr_step_event.phase, hsr_trace_event.phase). */
typedef struct hsr_phase_desc {
    uint32_t struct_size;
    const char* name;  /* lower-case words joined by '-', unique in the plugin's list */
    const char* title; /* a few words in English for a person, e.g. "depth test" */
} hsr_phase_desc;

/* What a line of a step shows (hsr_step_event.line_roles), for the colour a viewer draws it in. */
typedef enum hsr_step_role {
    HSR_STEP_SUBJECT = 0,  /* what the step works on: a triangle's outline, a tile or node box */
    HSR_STEP_WRITTEN = 1,  /* pixels that passed the depth test (a span), a box accepted */
    HSR_STEP_REJECTED = 2, /* pixels that failed it, a box culled */
    HSR_STEP_CONTEXT = 3   /* state the step works with: the active edges, the scanline */
} hsr_step_role;

/* One of the plugin's own buffers as it is at a step (a z-pyramid level, say), for a viewer to
 * show beside the frame: width * height values, row 0 at the top. */
typedef struct hsr_step_buffer {
    uint32_t struct_size;
    uint32_t width;
    uint32_t height;
    const char* name; /* lower-case words joined by '-', e.g. "z-pyramid-3" */
    const float* values;
} hsr_step_buffer;

#define HSR_NO_LEVEL 0xFFFFFFFFu

/* What one step did. Everything it points to is valid only during the step() call: the host copies
 * what it keeps. Fields that do not apply hold their "none" value (NULL, HSR_NO_FACE, HSR_NO_LEVEL,
 * zero counts). */
typedef struct hsr_step_event {
    uint32_t struct_size;
    const char* type; /* lower-case words joined by '-': "triangle", "scanline", "node-culled", ... */
    const char* text; /* one line for a person, e.g. "triangle 1204: 37 pixels written, 12 behind";
                         NULL: the host writes one from the other fields */
    uint32_t face;     /* the triangle the step is about, or HSR_NO_FACE */
    uint32_t instance; /* its instance; 0 when the scene has none */
    uint32_t level;    /* the pyramid or tree level concerned, or HSR_NO_LEVEL */
    uint32_t line_count;
    const float* lines;         /* 4 * line_count: x0, y0, x1, y1 in window coordinates (see
                                   hsr_camera), to draw over the picture */
    const uint32_t* line_roles; /* line_count hsr_step_role values, or NULL: all HSR_STEP_SUBJECT */
    uint64_t pixels_written;    /* depth tests passed in this step */
    uint64_t pixels_rejected;   /* depth tests failed in this step */
    const hsr_step_buffer* buffers;
    uint32_t buffer_count;
    /* Since 1.5: */
    const char* phase; /* the name of one of the plugin's phases, or NULL when it lists none */
} hsr_step_event;

typedef struct hsr_step_sink {
    void* context;
    /* Returns 0 to go on, non-zero to stop after this step (the host's step limit). */
    uint32_t (*step)(void* context, const hsr_step_event* event);
    /* Since 1.5 (read it only when built against 1.5 or later: an older host never loads such a
     * plugin): the language the host would like step texts in, an ISO 639-1 code in lower case
     * such as "en" or "ru"; NULL means English. A plugin without texts in that language writes
     * English. */
    const char* language;
} hsr_step_sink;

/* Since 1.4: fragment lists, for anti-aliasing and transparency (Carpenter's A-buffer). A fragment
 * is the part of one triangle inside one pixel, with a mask of the pixel's HSR_COVERAGE_SAMPLES
 * subsamples it covers: bit (8 * row + column) for the sample at (x + (column + 0.5) / 8,
 * y + (row + 0.5) / 4), a 4-row by 8-column grid. */
#define HSR_COVERAGE_SAMPLES 32

/* A batch of fragments, structure of arrays, valid only during the emit call. The fragments of one
 * pixel are consecutive, in one batch, nearest first; a pixel appears in at most one batch. A
 * plugin may leave out a fragment that opaque fragments nearer than it cover entirely. */
typedef struct hsr_pixel_fragments {
    uint32_t struct_size;
    uint32_t count;
    const uint32_t* pixel;    /* count: y * width + x */
    const uint32_t* face;     /* count: the triangle */
    const uint32_t* instance; /* count: its instance, or NULL when the scene has none */
    const float* depth;       /* count: window depth at the centroid of the covered samples */
    const uint32_t* coverage; /* count: the samples covered (non-zero) */
    const float* bary;        /* 2 * count: perspective-correct (b1, b2) of the triangle at the
                                 centroid of the covered samples, where the host shades it */
} hsr_pixel_fragments;

typedef struct hsr_fragment_sink {
    void* context;
    /* Returns HSR_OK, or an error the plugin passes on (then it stops and returns that status). */
    hsr_status (*emit)(void* context, const hsr_pixel_fragments* batch);
} hsr_fragment_sink;

typedef struct IHiddenSurfaceRemover {
    uint32_t struct_size;
    /* Makes an instance from validated parameters. On success *instance is set and HSR_OK returned. */
    hsr_status (*create)(const hsr_param_value* params, uint32_t param_count, void** instance,
                         hsr_error* error);
    /* Frees an instance. Never fails. */
    void (*destroy)(void* instance);
    /* Resolves visibility of the whole scene into target. counters may be NULL. May be called any
     * number of times on one instance, never concurrently. */
    hsr_status (*render)(void* instance, const hsr_scene* scene, const hsr_camera* camera,
                         hsr_visibility_buffer* target, const hsr_counter_sink* counters,
                         hsr_error* error);
    /* Optional extension tables by id (see docs/abi.md); NULL or returning NULL means none. */
    const void* (*extension)(const char* id);
    /* Since 1.3, optional (NULL: the algorithm has no steps to show): render() that calls
     * steps->step() at the end of each step of the algorithm and returns HSR_OK as soon as a call
     * answers non-zero, leaving target as the steps so far made it. Run to the end, it leaves
     * target exactly as render() does. When steps->step() is called, target already holds what
     * the steps so far wrote: a viewer copies it there to show what the next step changes. */
    hsr_status (*render_steps)(void* instance, const hsr_scene* scene, const hsr_camera* camera,
                               hsr_visibility_buffer* target, const hsr_counter_sink* counters,
                               const hsr_step_sink* steps, hsr_error* error);
    /* Since 1.4, optional (NULL: one surface per pixel, opaque scenes only): render(), which also
     * hands `fragments` the fragment lists of every pixel a surface touches, in batches. target is
     * filled as render() fills it. */
    hsr_status (*render_fragments)(void* instance, const hsr_scene* scene, const hsr_camera* camera,
                                   hsr_visibility_buffer* target, const hsr_counter_sink* counters,
                                   const hsr_fragment_sink* fragments, hsr_error* error);
} IHiddenSurfaceRemover;

/* ---------------------------------------------------------------------------------------------- */
/* Lighting                                                                                        */

/* What a lighting model needs besides the scene: the lights and where the viewer is. */
typedef struct hsr_shading_context {
    uint32_t struct_size;
    const hsr_light* lights;
    uint32_t light_count;
    uint32_t projection_type; /* an hsr_projection */
    float eye[3];            /* PERSPECTIVE: the view vector at P is normalize(eye - P) */
    float view_direction[3]; /* ORTHOGRAPHIC: the view vector is -view_direction everywhere */
} hsr_shading_context;

/* A batch of visible fragments in structure-of-arrays form, filled by the host from the visibility
 * buffer: one entry per covered pixel, each visible pixel exactly once per frame. The lighting model
 * writes color; everything else is read-only. */
typedef struct hsr_fragment_batch {
    uint32_t struct_size;
    uint32_t count;
    const uint32_t* face;   /* count: triangle index */
    const float* bary;      /* 2 * count: b1, b2 (corner 0 weight is 1 - b1 - b2) */
    const float* position;  /* 3 * count: world-space point on the triangle */
    const float* normal;    /* 3 * count: corner normals interpolated and renormalised */
    const uint32_t* pixel;  /* count: y * width + x, for plugins that care where they are */
    float* color;           /* 3 * count: output RGB, expected in [0, 1] (the host clamps) */
    /* Since 1.1: */
    const uint32_t* instance; /* count: the face's instance, or NULL when the scene has none;
                                 position and normal above are already in world space */
} hsr_fragment_batch;

typedef struct ILightingModel {
    uint32_t struct_size;
    hsr_status (*create)(const hsr_param_value* params, uint32_t param_count, void** instance,
                         hsr_error* error);
    void (*destroy)(void* instance);
    /* Called once per frame before any shade(): the scene and shading context stay valid and
     * unchanged until the next prepare() or destroy(). A model may precompute per face or per
     * corner here (flat and Gouraud shading do). */
    hsr_status (*prepare)(void* instance, const hsr_scene* scene,
                          const hsr_shading_context* context, hsr_error* error);
    /* Shades one batch. MUST be safe to call concurrently from several threads on one prepared
     * instance (it only reads what prepare() built and writes batch->color). */
    hsr_status (*shade)(const void* instance, hsr_fragment_batch* batch, hsr_error* error);
    const void* (*extension)(const char* id);
} ILightingModel;

/* ---------------------------------------------------------------------------------------------- */
/* Since 1.2: hidden-line removal                                                                  */

#define HSR_NO_EDGE 0xFFFFFFFFu

/* What kind of edge an edge of the request is (bits of hsr_line_request.edge_flags); the host
 * classifies edges for the camera of the call. A segment carries its edge's bits, or
 * HSR_EDGE_PENETRATION for a line a plugin made where two bodies intersect. */
#define HSR_EDGE_BOUNDARY 1u    /* one face only */
#define HSR_EDGE_CREASE 2u      /* its two faces meet at more than the host's crease angle */
#define HSR_EDGE_SILHOUETTE 4u  /* between a face turned toward the eye and one turned away */
#define HSR_EDGE_BACK 8u        /* every face it has is turned away from the eye */
#define HSR_EDGE_PENETRATION 16u /* segments only: where two bodies intersect (not a mesh edge) */

/* The edges whose visible (and, on request, hidden) pieces the host wants, as arrays of count
 * elements (structure of arrays). The scene a hidden-line remover gets never has instances (the host
 * copies them out), so vertex and face indices are those of hsr_scene. Every face of the scene hides
 * what is behind it, whether or not its edges are requested. */
typedef struct hsr_line_request {
    uint32_t struct_size;
    uint32_t edge_count;
    const uint32_t* edge_vertices; /* 2 * edge_count: the end points, indices into positions */
    const uint32_t* edge_faces;    /* 2 * edge_count: the faces sharing the edge; HSR_NO_FACE for
                                      the second one of a boundary edge */
    const uint32_t* edge_flags;    /* edge_count: HSR_EDGE_* bits */
    uint32_t want_hidden;          /* non-zero: also return the hidden pieces */
} hsr_line_request;

/* A batch of segments from the plugin, in window coordinates (x right, y down, in pixels, as for
 * pixel centres; see hsr_camera), valid only during the emit call: the host copies what it keeps. */
typedef struct hsr_segment_batch {
    uint32_t struct_size;
    uint32_t count;
    const float* points;   /* 4 * count: x0, y0, x1, y1 */
    const uint32_t* edge;  /* count: index into the request's edges, or HSR_NO_EDGE (penetration) */
    const uint32_t* flags; /* count: HSR_EDGE_* bits of the segment */
    const int32_t* qi;     /* count: quantitative invisibility, the number of faces between the
                              segment and the eye: 0 = visible; -1 = hidden, count not known */
} hsr_segment_batch;

typedef struct hsr_segment_sink {
    void* context;
    /* Returns HSR_OK, or an error the plugin passes on (then it stops and returns that status). */
    hsr_status (*emit)(void* context, const hsr_segment_batch* batch);
} hsr_segment_sink;

/* One step of an algorithm, for replaying it (e.g. "edge-begin", "hidden-by", "qi-change"): the
 * plugin says which fields mean something; the others hold their "none" values (HSR_NO_EDGE,
 * HSR_NO_FACE, HSR_NO_OBJECT, qi -1, t NaN). Valid only during the call. */
#define HSR_NO_OBJECT 0xFFFFFFFFu
typedef struct hsr_trace_event {
    uint32_t struct_size;
    const char* type;   /* lower-case words joined by '-' */
    uint32_t edge;      /* the edge being worked on */
    uint32_t face;      /* the face that hides it, bounds it, or changes its QI */
    uint32_t object;    /* the body (hsr_scene.face_object) concerned */
    int32_t qi;         /* quantitative invisibility after this step */
    double t0, t1;      /* parameters along the edge (0 at its first vertex, 1 at its second) */
    /* Since 1.3: what a viewer draws for this step, as in hsr_step_event. Read only when
     * struct_size covers them and the plugin claims minor 3 or later. */
    const char* text;           /* one line for a person, or NULL: the host writes one from the
                                   fields above */
    uint32_t line_count;
    const float* lines;         /* 4 * line_count: x0, y0, x1, y1 in window coordinates (see
                                   hsr_camera), to draw over the lines found so far */
    const uint32_t* line_roles; /* line_count hsr_step_role values, or NULL: all HSR_STEP_SUBJECT */
    /* Since 1.5: */
    const char* phase; /* the name of one of the plugin's phases, or NULL when it lists none */
} hsr_trace_event;

typedef struct hsr_trace_sink {
    void* context;
    void (*event)(void* context, const hsr_trace_event* event);
    /* Since 1.5: the language of step texts, as hsr_step_sink.language. */
    const char* language;
} hsr_trace_sink;

typedef struct IHiddenLineRemover {
    uint32_t struct_size;
    hsr_status (*create)(const hsr_param_value* params, uint32_t param_count, void** instance,
                         hsr_error* error);
    void (*destroy)(void* instance);
    /* Finds the visible pieces of the requested edges and hands them to segments in batches (the
     * hidden ones too when request->want_hidden). trace and counters may be NULL. Never concurrent
     * on one instance. */
    hsr_status (*render_lines)(void* instance, const hsr_scene* scene, const hsr_camera* camera,
                               const hsr_line_request* request, const hsr_segment_sink* segments,
                               const hsr_trace_sink* trace, const hsr_counter_sink* counters,
                               hsr_error* error);
    const void* (*extension)(const char* id);
} IHiddenLineRemover;

/* ---------------------------------------------------------------------------------------------- */
/* Discovery                                                                                       */

/* One of the plugin's texts in another language (since 1.6). `key` says which text it replaces:
 *   "description"              the descriptor's description
 *   "param:<name>"             a parameter's name as a person reads it, e.g. "тест глубины"
 *   "help:<name>"              a parameter's help line
 *   "choice:<param>:<choice>"  one choice of an ENUM parameter, e.g. "choice:depth-test:less"
 *   "phase:<name>"             a phase's title
 *   "counter:<name>"           a counter the plugin reports
 *   "buffer:<name>"            a step buffer; a name ending in "-<number>" may be translated
 *                              without it ("buffer:z-pyramid" covers "z-pyramid-3")
 *   "step:<type>"              the type of a step (hsr_step_event.type, hsr_trace_event.type) as a
 *                              person names it, e.g. "step:node-culled" -> "отсечённый узел"
 * The names inside keys are the plugin's own identifiers, which stay what the command line takes.
 * At most one entry per (language, key); the host refuses a list with duplicates, an empty text, a
 * language that is not two or three lower-case letters, or a key naming a parameter, choice or
 * phase the plugin does not have. Strings are static in the plugin library. */
typedef struct hsr_translation {
    uint32_t struct_size;
    const char* language; /* "ru": an ISO 639-1 code */
    const char* key;
    const char* text;
} hsr_translation;

typedef enum hsr_plugin_kind {
    HSR_KIND_HIDDEN_SURFACE_REMOVER = 1,
    HSR_KIND_LIGHTING_MODEL = 2,
    HSR_KIND_HIDDEN_LINE_REMOVER = 3 /* since 1.2 */
} hsr_plugin_kind;

typedef struct hsr_plugin_descriptor {
    /* Frozen for every ABI version: */
    uint32_t struct_size;
    const char* api;    /* HSR_API_NAME */
    uint32_t abi_major; /* HSR_ABI_MAJOR the plugin was built with */
    uint32_t abi_minor; /* HSR_ABI_MINOR the plugin was built with */
    uint32_t kind;      /* an hsr_plugin_kind */
    /* Since 1.0: */
    const char* name;        /* unique per kind, lower-case words joined by '-' */
    const char* version;     /* the plugin's own version, e.g. "1.0.0" */
    const char* description; /* one line */
    const hsr_param_desc* params;
    uint32_t param_count;
    /* Points to an IHiddenSurfaceRemover, an ILightingModel or an IHiddenLineRemover according to
     * kind. */
    const void* interface_table;
    /* Since 1.5: the phases its steps name, in the order the algorithm's pseudocode has them,
     * stepped by struct_size; NULL and 0 when its steps name none. */
    const hsr_phase_desc* phases;
    uint32_t phase_count;
    /* Since 1.6: its texts in other languages, stepped by struct_size; NULL and 0 when it has none. */
    const hsr_translation* translations;
    uint32_t translation_count;
} hsr_plugin_descriptor;

/* The one symbol a plugin library exports. Returns descriptor `index`, or NULL past the last one.
 * MUST NOT fail otherwise; the pointers stay valid while the library is loaded. */
typedef const hsr_plugin_descriptor* (*hsr_entry_fn)(uint32_t index);

/* ---------------------------------------------------------------------------------------------- */
/* Layout checks: the frozen descriptor prefix may never move, on any compiler that reads this file.
 * C++ and C11 use their static assertions; strict C99 gets an array whose size is -1 if a check
 * fails. */

#if defined(__cplusplus)
#define HSR_ABI_CHECK(condition, message) static_assert(condition, message)
#elif defined(__STDC_VERSION__) && __STDC_VERSION__ >= 201112L
#define HSR_ABI_CHECK(condition, message) _Static_assert(condition, message)
#else
#define HSR_ABI_CHECK(condition, message) extern char hsr_abi_check[(condition) ? 1 : -1]
#endif

HSR_ABI_CHECK(sizeof(uint32_t) == 4 && sizeof(float) == 4 && sizeof(double) == 8, "fixed-size scalars");
HSR_ABI_CHECK(offsetof(hsr_plugin_descriptor, struct_size) == 0, "frozen: descriptor struct_size");
HSR_ABI_CHECK(offsetof(hsr_plugin_descriptor, api) == sizeof(void*), "frozen: descriptor api");
HSR_ABI_CHECK(offsetof(hsr_plugin_descriptor, abi_major) == 2 * sizeof(void*), "frozen: descriptor abi_major");
HSR_ABI_CHECK(offsetof(hsr_plugin_descriptor, abi_minor) == 2 * sizeof(void*) + 4, "frozen: descriptor abi_minor");
HSR_ABI_CHECK(offsetof(hsr_plugin_descriptor, kind) == 2 * sizeof(void*) + 8, "frozen: descriptor kind");
HSR_ABI_CHECK(sizeof(((hsr_plugin_descriptor*)0)->kind) == 4, "frozen: descriptor kind is 4 bytes");
HSR_ABI_CHECK(sizeof(hsr_error) == HSR_ERROR_MESSAGE_SIZE, "hsr_error is the message buffer alone");
HSR_ABI_CHECK(sizeof(((hsr_param_desc*)0)->type) == 4 && sizeof(((hsr_param_value*)0)->type) == 4 &&
                  sizeof(((hsr_camera*)0)->projection_type) == 4 && sizeof(((hsr_light*)0)->type) == 4 &&
                  sizeof(((hsr_shading_context*)0)->projection_type) == 4,
              "enum-valued fields are uint32_t");

#undef HSR_ABI_CHECK

#ifdef __cplusplus
}
#endif

#endif /* HSR_ABI_H */
