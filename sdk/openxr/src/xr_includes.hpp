// OpenXR's headers with the one platform piece the layer uses: timespec time conversion.
#pragma once

#include <time.h>

#define XR_USE_TIMESPEC 1
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>
