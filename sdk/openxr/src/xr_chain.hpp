// Walking and editing OpenXR structure chains (the `next` pointers of app structures).
#pragma once

#include "xr_includes.hpp"

namespace fovea::openxr {

template <typename T>
T* find_in_chain(void* next, XrStructureType type) {
    for (auto* b = static_cast<XrBaseOutStructure*>(next); b; b = b->next)
        if (b->type == type) return reinterpret_cast<T*>(b);
    return nullptr;
}

// Takes a structure the layers below do not know out of an app's output chain for the length of
// one call, and puts it back. The app's chain is only touched during the call it made.
class ChainCut {
public:
    ChainCut(void* head, XrStructureType type) {
        auto* prev = static_cast<XrBaseOutStructure*>(head);
        while (prev && prev->next && prev->next->type != type) prev = prev->next;
        if (prev && prev->next) {
            prev_ = prev;
            cut_ = prev->next;
            prev->next = cut_->next;
        }
    }
    ~ChainCut() {
        if (prev_) prev_->next = cut_;
    }
    ChainCut(const ChainCut&) = delete;
    ChainCut& operator=(const ChainCut&) = delete;

private:
    XrBaseOutStructure* prev_ = nullptr;
    XrBaseOutStructure* cut_ = nullptr;
};

}  // namespace fovea::openxr
