/* Fovea shared-memory ring: the one binary contract between fovead (single writer) and any
 * number of read-only clients. Plain C, fixed-size types, no pointers: the same bytes are mapped
 * by processes built with different compilers. Every size and offset that matters is asserted
 * below; changing any of them means bumping FOVEA_RING_ABI_VERSION.
 *
 * Layout of one POSIX shm object ("/fovea.<instance>.<stream>"):
 *   fovea_ring_header (256 bytes) | slot_count x slot (slot_size bytes each)
 * A slot is a 64-bit sequence word followed by one record (fovea_gaze_record or
 * fovea_head_record, per header.stream_kind).
 *
 * Seqlock protocol, per slot, for the record with index i (0, 1, 2, ...; slot i % slot_count):
 *   writer: seq = 2i+1 (odd: writing), release fence, store record words (relaxed atomics),
 *           seq = 2i+2 (release), then header.head = i+1 (release), futex_word++ and FUTEX_WAKE.
 *   reader: s1 = seq (acquire); s1 == 2i+2 means record i is complete; copy the words (relaxed
 *           atomics), acquire fence, s2 = seq; s1 == s2 means the copy is untorn. s1 > 2i+2 means
 *           the writer lapped the reader (overrun).
 * Times are int64 nanoseconds of the host's CLOCK_MONOTONIC. */
#ifndef FOVEA_RING_H
#define FOVEA_RING_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define FOVEA_RING_MAGIC 0x474E495241564F46ull /* "FOVARING" little-endian */
#define FOVEA_RING_ABI_VERSION 1u
#define FOVEA_RING_DEFAULT_SLOTS 4096u

/* Which record type the slots of a ring carry. */
typedef enum fovea_stream_kind {
    FOVEA_STREAM_GAZE = 1, /* fovea_gaze_record */
    FOVEA_STREAM_HEAD = 2  /* fovea_head_record */
} fovea_stream_kind;

/* Writer state, header.state. */
typedef enum fovea_ring_state {
    FOVEA_RING_INITIALIZING = 0,
    FOVEA_RING_LIVE = 1,
    FOVEA_RING_CLOSED = 2 /* the writer shut down cleanly; a new generation may follow */
} fovea_ring_state;

/* Per-sample eye-movement event, record.event. */
typedef enum fovea_event {
    FOVEA_EVENT_UNKNOWN = 0,
    FOVEA_EVENT_FIXATION = 1,
    FOVEA_EVENT_SACCADE = 2,
    FOVEA_EVENT_PSO = 3, /* post-saccadic oscillation */
    FOVEA_EVENT_PURSUIT = 4,
    FOVEA_EVENT_BLINK = 5
} fovea_event;

/* record.flags / fovea_eye.valid bits. */
#define FOVEA_VALID 1u                 /* the eye (or combined gaze) is tracked */
#define FOVEA_FLAG_LANDING_VALID 2u    /* the saccade landing prediction is set */
#define FOVEA_FLAG_CALIBRATED 4u       /* gaze went through a user calibration */
#define FOVEA_FLAG_SIMULATED 8u        /* from the built-in simulated tracker */
#define FOVEA_FLAG_CLOCK_CONVERGED 16u /* device clock mapping has converged */
#define FOVEA_FLAG_PROVISIONAL                                  \
    32u /* published live, before the detector's look-ahead:    \
         * event labels are causal (saccade in flight, blink or \
         * unknown); the final labels go to recordings/observers */

/* One eye's gaze. Normalized display coordinates: 0..1, origin top-left. Degrees: visual angle
 * from the display centre, +x right, +y down, from the configured display geometry. */
typedef struct fovea_eye {
    float norm_x, norm_y;
    float deg_x, deg_y;
    float pupil_mm; /* pupil diameter; 0 where the tracker does not report it */
    uint32_t valid; /* FOVEA_VALID or 0 */
} fovea_eye;

/* A processed gaze sample (stream kind FOVEA_STREAM_GAZE). 192 bytes. */
typedef struct fovea_gaze_record {
    uint64_t index;         /* 0, 1, 2, ... within this writer generation */
    int64_t t_capture_ns;   /* device capture time mapped to host CLOCK_MONOTONIC */
    int64_t t_receive_ns;   /* host time the bytes arrived */
    int64_t t_processed_ns; /* host time filtering/detection/prediction finished */
    int64_t t_publish_ns;   /* host time the record was written into the ring */
    fovea_eye left, right, combined;
    uint32_t event;             /* fovea_event */
    uint32_t flags;             /* FOVEA_FLAG_* */
    uint32_t device_id;         /* index of the device in the daemon's configuration */
    float clock_uncertainty_us; /* the clock mapping's own uncertainty estimate */
    /* Saccade fields: meaningful while event == FOVEA_EVENT_SACCADE (and briefly after). */
    int64_t saccade_onset_ns;
    float saccade_amplitude_deg; /* amplitude so far (in flight) or final */
    float saccade_peak_velocity_dps;
    float saccade_direction_deg;          /* atan2(dy, dx) of the movement, degrees */
    float landing_norm_x, landing_norm_y; /* predicted landing point, FOVEA_FLAG_LANDING_VALID */
    float landing_deg_x, landing_deg_y;
    float landing_uncertainty_deg; /* 1-sigma radius of the landing prediction */
    uint64_t reserved[2];
    uint64_t checksum; /* fovea_record_checksum() of every byte before this field */
} fovea_gaze_record;

/* A head pose sample (stream kind FOVEA_STREAM_HEAD), from head trackers (HID usage 0x02). */
typedef struct fovea_head_record {
    uint64_t index;
    int64_t t_capture_ns;
    int64_t t_receive_ns;
    int64_t t_processed_ns;
    int64_t t_publish_ns;
    float position_m[3];    /* head position, metres, tracker frame */
    float direction[3];     /* unit forward direction */
    float rotation_quat[4]; /* x, y, z, w */
    uint32_t valid;         /* bits: 1 position, 2 direction, 4 rotation */
    uint32_t device_id;
    uint64_t reserved[12];
    uint64_t checksum;
} fovea_head_record;

/* The HMD eye geometry the writer maps gaze with (fovead's display_profile), so a reader can turn
 * each eye's normalized display coordinates into a view direction: per eye the half-angles of its
 * view from the optical axis (degrees, as in drivers/profiles: left, right, up, down) and the
 * interpupillary distance. All zero when the writer has no HMD profile (a monitor, or a writer
 * from before this field: the bytes were reserved and zero). 36 bytes. */
typedef struct fovea_eye_geometry {
    float fov_deg[2][4]; /* [0 left eye, 1 right eye][0 left, 1 right, 2 up, 3 down] */
    float ipd_m;         /* 0: no geometry */
} fovea_eye_geometry;

/* The slot's payload: both record types fit in it. */
#define FOVEA_RING_RECORD_BYTES 192u

typedef struct fovea_ring_header {
    uint64_t magic;       /* FOVEA_RING_MAGIC */
    uint32_t abi_version; /* FOVEA_RING_ABI_VERSION */
    uint32_t header_size; /* sizeof(fovea_ring_header) */
    uint32_t slot_size;   /* bytes per slot: 8 (seq) + record, padded to 64 */
    uint32_t record_size; /* sizeof the record type */
    uint32_t slot_count;  /* power of two */
    uint32_t stream_kind; /* fovea_stream_kind */
    uint64_t generation;  /* random, new every time a writer creates the ring */
    int64_t created_ns;   /* CLOCK_MONOTONIC at creation */
    uint32_t writer_pid;
    uint32_t nominal_rate_hz; /* the device's sampling rate, 0 until known; the writer updates
                                 it (atomically) when it measures a tracker's rate */
    char stream_name[32];     /* NUL-terminated, e.g. "gaze" */
    char device_name[64];     /* NUL-terminated, e.g. "sim" */
    fovea_eye_geometry eyes;  /* set once at creation; ipd_m == 0 when absent */
    uint8_t reserved0[4];
    /* Writer-owned, updated on every publish: on its own cache line (offset 192). */
    uint64_t head;       /* number of records published; the newest is head - 1 */
    uint32_t futex_word; /* incremented with every publish; readers FUTEX_WAIT on it */
    uint32_t state;      /* fovea_ring_state */
    uint8_t reserved1[48];
} fovea_ring_header;

#define FOVEA_RING_SLOT_SIZE 256u /* 8-byte sequence + 192-byte record, padded to 64 bytes */

#ifdef __cplusplus
#define FOVEA_STATIC_ASSERT(c, m) static_assert(c, m)
#else
#define FOVEA_STATIC_ASSERT(c, m) _Static_assert(c, m)
#endif

FOVEA_STATIC_ASSERT(sizeof(fovea_eye) == 24, "fovea_eye size is ABI");
FOVEA_STATIC_ASSERT(sizeof(fovea_gaze_record) == FOVEA_RING_RECORD_BYTES,
                    "gaze record size is ABI");
FOVEA_STATIC_ASSERT(sizeof(fovea_head_record) == FOVEA_RING_RECORD_BYTES,
                    "head record size is ABI");
FOVEA_STATIC_ASSERT(sizeof(fovea_ring_header) == 256, "ring header size is ABI");
FOVEA_STATIC_ASSERT(__builtin_offsetof(fovea_ring_header, head) == 192, "head on its own line");
FOVEA_STATIC_ASSERT(sizeof(fovea_eye_geometry) == 36, "eye geometry size is ABI");
FOVEA_STATIC_ASSERT(__builtin_offsetof(fovea_ring_header, eyes) == 152, "header layout is ABI");
FOVEA_STATIC_ASSERT(__builtin_offsetof(fovea_gaze_record, left) == 40, "record layout is ABI");
FOVEA_STATIC_ASSERT(__builtin_offsetof(fovea_gaze_record, event) == 112, "record layout is ABI");
FOVEA_STATIC_ASSERT(__builtin_offsetof(fovea_gaze_record, saccade_onset_ns) == 128,
                    "record layout is ABI");
FOVEA_STATIC_ASSERT(__builtin_offsetof(fovea_gaze_record, checksum) == 184, "record layout is ABI");
FOVEA_STATIC_ASSERT(__builtin_offsetof(fovea_head_record, checksum) == 184, "record layout is ABI");
FOVEA_STATIC_ASSERT(FOVEA_RING_SLOT_SIZE % 64 == 0 &&
                        FOVEA_RING_SLOT_SIZE >= 8 + FOVEA_RING_RECORD_BYTES,
                    "slot holds sequence + record on whole cache lines");

/* FNV-1a-style 64-bit hash over the record's 8-byte words before its checksum field (both
 * record types keep the checksum as the last 8 bytes). Lets tests and paranoid clients prove a
 * copy is untorn. The record must be 8-byte aligned. */
static inline uint64_t fovea_record_checksum(const void* record) {
    const uint64_t* w = (const uint64_t*)record;
    uint64_t h = 1469598103934665603ull;
    for (unsigned i = 0; i < FOVEA_RING_RECORD_BYTES / 8u - 1u; ++i) {
        h ^= w[i];
        h *= 1099511628211ull;
        h ^= h >> 29;
    }
    return h;
}

#ifdef __cplusplus
}
#endif

#endif /* FOVEA_RING_H */
