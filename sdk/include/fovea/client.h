/* libfovea client: read the gaze (and head-pose) rings that fovead publishes. C ABI.
 *
 * Every function returns FOVEA_OK (0) or a negative fovea_status; on failure the text of
 * fovea_last_error() (thread-local) says what went wrong. No function throws, allocates after
 * open/create, or takes a lock: readers never slow the writer down, and a client killed mid-read
 * leaves nothing behind. (fovea_frame_latency_report, below, does blocking socket I/O.) One
 * fovea_client may be used by one thread at a time; open one per thread if several threads read.
 *
 * Typical loop:
 *   fovea_client* c = NULL;
 *   if (fovea_client_open("default", FOVEA_STREAM_GAZE, &c) != FOVEA_OK) {
 * puts(fovea_last_error()); } uint64_t cursor = fovea_client_head(c); for (;;) {
 *       fovea_client_wait(c, cursor, 100);
 *       fovea_gaze_record r[64]; uint32_t n = 0; uint64_t dropped = 0;
 *       fovea_client_read(c, &cursor, r, 64, &n, &dropped);
 *   }
 *   fovea_client_close(&c);
 */
#ifndef FOVEA_CLIENT_H
#define FOVEA_CLIENT_H

#include <stddef.h>
#include <stdint.h>

#include "fovea/ring.h"

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define FOVEA_API __attribute__((visibility("default")))
#else
#define FOVEA_API
#endif

typedef enum fovea_status {
    FOVEA_OK = 0,
    FOVEA_E_INVALID_ARGUMENT = -1,
    FOVEA_E_NOT_FOUND = -2,        /* no such ring: is fovead running with that instance? */
    FOVEA_E_INCOMPATIBLE = -3,     /* magic, ABI version or sizes differ from this library */
    FOVEA_E_TIMEOUT = -4,          /* fovea_client_wait: nothing new within the timeout */
    FOVEA_E_NO_DATA = -5,          /* nothing published yet */
    FOVEA_E_WRITER_RESTARTED = -6, /* a new writer generation: the client re-attached to it and
                                      the caller's cursor must restart from fovea_client_head() */
    FOVEA_E_SYSTEM = -7,           /* an OS call failed; fovea_last_error() has errno's text */
    FOVEA_E_WRONG_STREAM = -8,     /* gaze call on a head-pose ring or vice versa */
    FOVEA_E_REJECTED = -9          /* fovead refused a control request; fovea_last_error() has
                                      the daemon's reason */
} fovea_status;

typedef struct fovea_client fovea_client;

/* What a client knows about the ring it is attached to. */
typedef struct fovea_ring_info {
    uint64_t generation;
    uint32_t slot_count;
    uint32_t stream_kind;
    uint32_t nominal_rate_hz; /* 0 until known: a rate the daemon measures appears later */
    uint32_t writer_pid;
    char stream_name[32];
    char device_name[64];
} fovea_ring_info;

/* Text for the calling thread's last failure; never NULL, "" if none. */
FOVEA_API const char* fovea_last_error(void);
/* Static name of a status code, e.g. "FOVEA_E_TIMEOUT". */
FOVEA_API const char* fovea_status_string(int status);
/* The ring ABI version this library was built for (FOVEA_RING_ABI_VERSION). */
FOVEA_API uint32_t fovea_abi_version(void);

/* The shm object name of an instance's stream: "/fovea.<instance>.gaze" or ".head".
 * Writes at most `capacity` bytes including the NUL; FOVEA_E_INVALID_ARGUMENT if it does not fit
 * or the instance name holds characters other than [A-Za-z0-9_-]. */
FOVEA_API int fovea_ring_name(const char* instance, fovea_stream_kind kind, char* out_name,
                              size_t capacity);

/* Attach read-only to the ring of `instance` (NULL or "" means "default"). */
FOVEA_API int fovea_client_open(const char* instance, fovea_stream_kind kind,
                                fovea_client** out_client);
/* Detach and free; sets *client to NULL. Safe on NULL. */
FOVEA_API void fovea_client_close(fovea_client** client);

FOVEA_API int fovea_client_info(const fovea_client* client, fovea_ring_info* out_info);
/* The HMD eye geometry the writer maps gaze with (ring.h, fovea_eye_geometry); all zero (ipd_m
 * == 0) when it has none. Changes only with a new writer generation. */
FOVEA_API int fovea_client_eye_geometry(const fovea_client* client,
                                        fovea_eye_geometry* out_geometry);

/* Number of records published so far in this generation: the next record's index. */
FOVEA_API uint64_t fovea_client_head(const fovea_client* client);

/* The newest complete gaze record. FOVEA_E_NO_DATA before the first publish. */
FOVEA_API int fovea_client_latest(fovea_client* client, fovea_gaze_record* out_record);

/* Copy up to `capacity` gaze records with index >= *cursor, oldest first, and advance *cursor
 * past them. If the writer lapped the reader, the records that were overwritten are skipped and
 * counted in *out_dropped (may be NULL). */
FOVEA_API int fovea_client_read(fovea_client* client, uint64_t* cursor,
                                fovea_gaze_record* out_records, uint32_t capacity,
                                uint32_t* out_count, uint64_t* out_dropped);

/* Head-pose equivalents, for rings of kind FOVEA_STREAM_HEAD. */
FOVEA_API int fovea_client_latest_head(fovea_client* client, fovea_head_record* out_record);
FOVEA_API int fovea_client_read_head(fovea_client* client, uint64_t* cursor,
                                     fovea_head_record* out_records, uint32_t capacity,
                                     uint32_t* out_count, uint64_t* out_dropped);

/* Block until a record with index >= cursor exists (returns FOVEA_OK at once if it does), or
 * `timeout_ms` passes (FOVEA_E_TIMEOUT; a negative timeout waits forever). Sleeps on a futex
 * on the ring header; by default no CPU is burnt. Detects a restarted writer
 * (FOVEA_E_WRITER_RESTARTED). */
FOVEA_API int fovea_client_wait(fovea_client* client, uint64_t cursor, int32_t timeout_ms);

/* Opt-in spin for fovea_client_wait, for a reader with a core of its own: waiting for the very
 * next record of a writer with a steady cadence (learned from the records' publish stamps), it
 * wakes from the futex sleep just before the record is due (early by the timer lateness it has
 * learned) and spins through a window of at most 1/8 of the writer's interval, once per record,
 * so the record is seen without the scheduler's wake-up latency. max_spin_us: 0 never spin (the
 * default), < 0 adaptive (1/8 of the interval), > 0 at most that many microseconds per record.
 * On an oversubscribed machine the spinner is preempted and this is slower than sleeping
 * (tests/ring/ring_latency_bench measures both). */
FOVEA_API int fovea_client_set_wait_spin(fovea_client* client, int32_t max_spin_us);

/* Check whether the writer was restarted or closed and, if so, re-attach to the new generation
 * (FOVEA_E_WRITER_RESTARTED) or report FOVEA_OK if nothing changed. The read calls do this by
 * themselves at most every 100 ms when they find nothing new. */
FOVEA_API int fovea_client_check(fovea_client* client);

/* ---- Render-side latency: the frame events a host reports -----------------------------------
 *
 * fovead measures a sample's device-side hops (capture -> receive -> processed -> publish). What
 * happens after publish only the host knows, so it reports it here: every gaze record it reads,
 * and for every frame the record the frame uses (frame begin), when its command buffer was
 * submitted and, where the host knows it, when it was presented. libfovea keeps one log-bucketed
 * histogram per render hop (fovea/latency_histogram.hpp: fixed size, about 19 KB per hop,
 * percentiles within 0.8 %), counts frames rendered with stale gaze, and sends everything to
 * fovead with fovea_frame_latency_report(), so `fovea latency` and `fovea status` show all hops.
 *
 *   fovea_frame_latency* fl = NULL;
 *   fovea_frame_latency_create(&fl);
 *   per frame:
 *     fovea_client_latest(c, &r);  fovea_frame_gaze_read(fl, &r, 0);
 *     int64_t age_ns = 0;          fovea_frame_begin(fl, &r, 0, &age_ns);  // widen by age_ns
 *     ... record, vkQueueSubmit ...  fovea_frame_submitted(fl, 0);
 *     ... vkQueuePresentKHR ...      fovea_frame_presented(fl, 0);        // optional
 *   about once a second:           fovea_frame_latency_report(fl, "default", 500);
 *
 * Times are CLOCK_MONOTONIC nanoseconds (the clock of the ring's stamps); 0 means "now".
 * Threads: the event calls (gaze_read, frame_*, reset, set_stale_threshold) on one object must
 * not run concurrently: one object per render thread, or serialise them. fovea_frame_latency_hop,
 * _counters and _report may run on any thread while events are recorded (each histogram is read
 * whole; it may be a few samples behind); _report on one thread at a time.
 */
typedef struct fovea_frame_latency fovea_frame_latency;

/* The render hops, in a sample's order; the first four continue the daemon's three device hops,
 * the last three are the gaze's age at points of the frame. Names: fovea_render_hop_name(). */
typedef enum fovea_render_hop {
    FOVEA_HOP_PUBLISH_TO_READ = 0,        /* "publish_to_read": ring publish -> host read it */
    FOVEA_HOP_READ_TO_FRAME_BEGIN = 1,    /* "read_to_frame_begin": that read -> the frame using
                                             the record begins */
    FOVEA_HOP_FRAME_BEGIN_TO_SUBMIT = 2,  /* "frame_begin_to_submit": -> command buffer submitted */
    FOVEA_HOP_SUBMIT_TO_PRESENT = 3,      /* "submit_to_present": -> presented (host-reported) */
    FOVEA_HOP_CAPTURE_TO_FRAME_BEGIN = 4, /* "capture_to_frame_begin": the gaze's age at frame
                                             begin (device capture -> begin); the stale test */
    FOVEA_HOP_PUBLISH_TO_FRAME_BEGIN = 5, /* "publish_to_frame_begin" */
    FOVEA_HOP_CAPTURE_TO_PRESENT = 6,     /* "capture_to_present": eye to photon, where known */
    FOVEA_RENDER_HOP_COUNT = 7
} fovea_render_hop;

/* Gaze older than this at frame begin counts as stale unless the host sets its own threshold:
 * Albert et al. 2017 found 20-40 ms of eye-tracking latency tolerable and 80-150 ms not. Hosts
 * that know their begin -> present time should subtract it (the budget is eye to photon). */
#define FOVEA_STALE_GAZE_DEFAULT_NS 40000000LL

/* One hop's histogram summary, nanoseconds. Percentiles are bucket midpoints within 0.8 % of
 * the true sample; 0 while count == 0. `negative` counts intervals that ran backwards (e.g. a
 * device clock mapping that put capture after the host read); they are recorded as 0 ns. */
typedef struct fovea_hop_stats {
    uint64_t count;
    uint64_t negative;
    int64_t p50_ns, p90_ns, p99_ns, p999_ns;
    int64_t min_ns, max_ns;
    double mean_ns;
} fovea_hop_stats;

typedef struct fovea_frame_counters {
    uint64_t frames;              /* fovea_frame_begin calls */
    uint64_t stale_frames;        /* of which the gaze was older than the threshold, or absent */
    uint64_t frames_without_gaze; /* of which no gaze record was given (nothing published yet) */
    uint64_t submitted;           /* fovea_frame_submitted calls that matched an open frame */
    uint64_t presented;           /* fovea_frame_presented calls that matched a submitted frame */
    int64_t stale_threshold_ns;
} fovea_frame_counters;

/* Static name of a hop ("publish_to_read", ...), the key fovead and `fovea latency` use; NULL
 * for a value outside [0, FOVEA_RENDER_HOP_COUNT). */
FOVEA_API const char* fovea_render_hop_name(int hop);

/* Empty histograms, stale threshold FOVEA_STALE_GAZE_DEFAULT_NS. All memory is taken here. */
FOVEA_API int fovea_frame_latency_create(fovea_frame_latency** out);
/* Free; sets *frame_latency to NULL. Safe on NULL. */
FOVEA_API void fovea_frame_latency_destroy(fovea_frame_latency** frame_latency);
/* Frames whose gaze is older than threshold_ns (> 0) at frame begin count as stale. */
FOVEA_API int fovea_frame_latency_set_stale_threshold(fovea_frame_latency* fl,
                                                      int64_t threshold_ns);
/* Zero the histograms and counters (the threshold stays). */
FOVEA_API void fovea_frame_latency_reset(fovea_frame_latency* fl);

/* The host read `record` from the ring at t_read_ns: records publish -> read. Call it for every
 * record read, or at least for the one the next frame will use (frame begin pairs with the most
 * recently read record to measure read -> frame begin). */
FOVEA_API int fovea_frame_gaze_read(fovea_frame_latency* fl, const fovea_gaze_record* record,
                                    int64_t t_read_ns);
/* A frame begins at t_begin_ns rendering for `record` (NULL: no gaze yet; the frame is counted
 * stale and without gaze). Records read -> begin (when `record` is the last one read) and the
 * gaze's age; *out_gaze_age_ns (may be NULL) receives capture -> begin, the age to widen the
 * fovea by (fovea::vk::GazeState::age_s), or -1 without a record. A frame left open (never
 * submitted) is simply replaced. */
FOVEA_API int fovea_frame_begin(fovea_frame_latency* fl, const fovea_gaze_record* record,
                                int64_t t_begin_ns, int64_t* out_gaze_age_ns);
/* The open frame's command buffer was submitted. FOVEA_E_NO_DATA if no frame is open. */
FOVEA_API int fovea_frame_submitted(fovea_frame_latency* fl, int64_t t_submit_ns);
/* The submitted frame was presented (closes the frame). FOVEA_E_NO_DATA if none was submitted. */
FOVEA_API int fovea_frame_presented(fovea_frame_latency* fl, int64_t t_present_ns);

FOVEA_API int fovea_frame_latency_hop(const fovea_frame_latency* fl, fovea_render_hop hop,
                                      fovea_hop_stats* out_stats);
FOVEA_API int fovea_frame_latency_counters(const fovea_frame_latency* fl,
                                           fovea_frame_counters* out_counters);

/* Send every hop's histogram (whole, mergeable) and the frame counters to the fovead of
 * `instance` (NULL or "" = "default") as the control command `latency.report`, over its socket
 * in the daemon's runtime directory (FOVEA_RUNTIME_DIR, else $RUNTIME_DIRECTORY, /run/fovea,
 * $XDG_RUNTIME_DIR/fovea, /tmp/fovea-<uid>, as fovead chooses). Each report replaces this
 * process's previous one in the daemon, so report the same object (cumulative) every time; one
 * reporting object per process. Blocks up to timeout_ms for the reply. FOVEA_E_NOT_FOUND: no
 * daemon listening; FOVEA_E_TIMEOUT; FOVEA_E_REJECTED: the daemon refused it. */
FOVEA_API int fovea_frame_latency_report(const fovea_frame_latency* fl, const char* instance,
                                         int32_t timeout_ms);

#ifdef __cplusplus
}
#endif

#endif /* FOVEA_CLIENT_H */
