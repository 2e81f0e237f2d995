// The thread-local error text behind fovea_last_error(), shared by every C-ABI source of
// libfovea (ring client, frame latency). Internal: hidden by the library's visibility preset.
#pragma once

namespace fovea::client_detail {

// Format the calling thread's last-error text and return `status`, so a failing path reads
// `return fail(FOVEA_E_..., "what happened: %s", why);`.
int fail(int status, const char* fmt, ...) __attribute__((format(printf, 2, 3)));

// The calling thread's buffer (never NULL).
const char* last_error();

}  // namespace fovea::client_detail
