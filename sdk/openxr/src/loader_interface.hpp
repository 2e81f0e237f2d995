// The OpenXR loader <-> API layer negotiation interface, as the loader specification
// ("API Layer Interaction", OpenXR loader design document) defines it. Debian's libopenxr-dev
// 1.0.20 does not install the loader's own header for it (openxr_loader_negotiation.h came with
// 1.0.29), so the layer declares the structures here; their layout is the loader's ABI.
#pragma once

#include <openxr/openxr.h>

#include <cstddef>
#include <cstdint>

extern "C" {

enum XrLoaderInterfaceStructs {
    XR_LOADER_INTERFACE_STRUCT_UNINTIALIZED = 0,
    XR_LOADER_INTERFACE_STRUCT_LOADER_INFO,
    XR_LOADER_INTERFACE_STRUCT_API_LAYER_REQUEST,
    XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST,
    XR_LOADER_INTERFACE_STRUCT_API_LAYER_CREATE_INFO,
    XR_LOADER_INTERFACE_STRUCT_API_LAYER_NEXT_INFO,
};

constexpr uint32_t kLoaderInfoStructVersion = 1;
constexpr uint32_t kApiLayerInfoStructVersion = 1;
constexpr uint32_t kApiLayerNextInfoStructVersion = 1;
constexpr uint32_t kApiLayerCreateInfoStructVersion = 1;
constexpr uint32_t kLoaderApiLayerInterfaceVersion = 1;
constexpr std::size_t kApiLayerMaxSettingsPathSize = 512;

struct XrNegotiateLoaderInfo {
    XrLoaderInterfaceStructs structType;
    uint32_t structVersion;
    std::size_t structSize;
    uint32_t minInterfaceVersion;
    uint32_t maxInterfaceVersion;
    XrVersion minApiVersion;
    XrVersion maxApiVersion;
};

struct XrApiLayerCreateInfo;
using PFN_xrCreateApiLayerInstance = XrResult(XRAPI_PTR*)(const XrInstanceCreateInfo* info,
                                                          const XrApiLayerCreateInfo* layerInfo,
                                                          XrInstance* instance);

struct XrNegotiateApiLayerRequest {
    XrLoaderInterfaceStructs structType;
    uint32_t structVersion;
    std::size_t structSize;
    uint32_t layerInterfaceVersion;
    XrVersion layerApiVersion;
    PFN_xrGetInstanceProcAddr getInstanceProcAddr;
    PFN_xrCreateApiLayerInstance createApiLayerInstance;
};

struct XrApiLayerNextInfo {
    XrLoaderInterfaceStructs structType;
    uint32_t structVersion;
    std::size_t structSize;
    char layerName[XR_MAX_API_LAYER_NAME_SIZE];
    PFN_xrGetInstanceProcAddr nextGetInstanceProcAddr;
    PFN_xrCreateApiLayerInstance nextCreateApiLayerInstance;
    XrApiLayerNextInfo* next;
};

struct XrApiLayerCreateInfo {
    XrLoaderInterfaceStructs structType;
    uint32_t structVersion;
    std::size_t structSize;
    void* loaderInstance;
    char settings_file_location[kApiLayerMaxSettingsPathSize];
    XrApiLayerNextInfo* nextInfo;
};

}  // extern "C"
