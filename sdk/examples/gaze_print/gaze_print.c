/* gaze_print: a minimal host application using the installed Fovea SDK. It attaches to a running
 * fovead's gaze ring and prints one line per sample:
 *   gaze_print [--instance NAME] [--count N] [--timeout-ms MS]
 * Exit status: 0 after N samples, 1 when the daemon is not there or sends nothing in time. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <fovea/client.h>

static const char* event_name(uint32_t e) {
    static const char* names[] = {"unknown", "fixation", "saccade", "pso", "pursuit", "blink"};
    return e < sizeof names / sizeof names[0] ? names[e] : "unknown";
}

int main(int argc, char** argv) {
    const char* instance = "default";
    long count = 10;
    int timeout_ms = 2000;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--instance") && i + 1 < argc)
            instance = argv[++i];
        else if (!strcmp(argv[i], "--count") && i + 1 < argc)
            count = strtol(argv[++i], NULL, 10);
        else if (!strcmp(argv[i], "--timeout-ms") && i + 1 < argc)
            timeout_ms = atoi(argv[++i]);
        else {
            fprintf(stderr, "usage: %s [--instance NAME] [--count N] [--timeout-ms MS]\n", argv[0]);
            return 2;
        }
    }

    fovea_client* client = NULL;
    int s = fovea_client_open(instance, FOVEA_STREAM_GAZE, &client);
    if (s != FOVEA_OK) {
        fprintf(stderr, "gaze_print: %s: %s\n", fovea_status_string(s), fovea_last_error());
        return 1;
    }
    fovea_ring_info info;
    if (fovea_client_info(client, &info) == FOVEA_OK)
        printf("# fovea ABI %u, instance %s, device %s, %u Hz\n", fovea_abi_version(), instance,
               info.device_name, info.nominal_rate_hz);

    uint64_t cursor = fovea_client_head(client);
    long printed = 0;
    uint64_t dropped_total = 0;
    while (printed < count) {
        s = fovea_client_wait(client, cursor, timeout_ms);
        if (s == FOVEA_E_WRITER_RESTARTED) {
            cursor = fovea_client_head(client);
            continue;
        }
        if (s != FOVEA_OK) {
            fprintf(stderr, "gaze_print: waiting for gaze: %s: %s\n", fovea_status_string(s),
                    fovea_last_error());
            fovea_client_close(&client);
            return 1;
        }
        fovea_gaze_record r[64];
        uint32_t n = 0;
        uint64_t dropped = 0;
        s = fovea_client_read(client, &cursor, r, 64, &n, &dropped);
        if (s == FOVEA_E_WRITER_RESTARTED) {
            cursor = fovea_client_head(client);
            continue;
        }
        if (s != FOVEA_OK) {
            fprintf(stderr, "gaze_print: %s: %s\n", fovea_status_string(s), fovea_last_error());
            fovea_client_close(&client);
            return 1;
        }
        dropped_total += dropped;
        for (uint32_t i = 0; i < n && printed < count; ++i, ++printed)
            printf("%llu %.6f %.4f %.4f %s\n", (unsigned long long)r[i].index,
                   (double)r[i].t_capture_ns / 1e9, r[i].combined.norm_x, r[i].combined.norm_y,
                   event_name(r[i].event));
    }
    if (dropped_total)
        fprintf(stderr, "gaze_print: %llu samples overrun\n", (unsigned long long)dropped_total);
    fovea_client_close(&client);
    return 0;
}
