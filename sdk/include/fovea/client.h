/* libfovea client: read the gaze (and head-pose) rings that fovead publishes. C ABI.
 *
 * Every function returns FOVEA_OK (0) or a negative fovea_status; on failure the text of
 * fovea_last_error() (thread-local) says what went wrong. No function throws, allocates after
 * open, or takes a lock: readers never slow the writer down, and a client killed mid-read leaves
 * nothing behind. One fovea_client may be used by one thread at a time; open one per thread if
 * several threads read.
 *
 * Typical loop:
 *   fovea_client* c = NULL;
 *   if (fovea_client_open("default", FOVEA_STREAM_GAZE, &c) != FOVEA_OK) { puts(fovea_last_error()); }
 *   uint64_t cursor = fovea_client_head(c);
 *   for (;;) {
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
    FOVEA_E_WRONG_STREAM = -8      /* gaze call on a head-pose ring or vice versa */
} fovea_status;

typedef struct fovea_client fovea_client;

/* What a client knows about the ring it is attached to. */
typedef struct fovea_ring_info {
    uint64_t generation;
    uint32_t slot_count;
    uint32_t stream_kind;
    uint32_t nominal_rate_hz;
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
 * on the ring header; no CPU is burnt. Detects a restarted writer (FOVEA_E_WRITER_RESTARTED). */
FOVEA_API int fovea_client_wait(fovea_client* client, uint64_t cursor, int32_t timeout_ms);

/* Check whether the writer was restarted or closed and, if so, re-attach to the new generation
 * (FOVEA_E_WRITER_RESTARTED) or report FOVEA_OK if nothing changed. The read calls do this by
 * themselves at most every 100 ms when they find nothing new. */
FOVEA_API int fovea_client_check(fovea_client* client);

#ifdef __cplusplus
}
#endif

#endif /* FOVEA_CLIENT_H */
