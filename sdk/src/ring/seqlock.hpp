// The seqlock primitives shared by the ring writer (fovead) and reader (libfovea).
// Protocol and layout: sdk/include/fovea/ring.h.
#pragma once

#include <cstdint>
#include <cstring>

#include "fovea/ring.h"

namespace fovea::ring {

inline constexpr std::size_t kRecordWords = FOVEA_RING_RECORD_BYTES / 8;

// Pointers into one mapped ring object. The mapping is read-only for readers.
struct RingView {
    fovea_ring_header* header = nullptr;
    unsigned char* slots = nullptr;
    uint64_t slot_mask = 0;

    uint64_t* seq_of(uint64_t index) const {
        return reinterpret_cast<uint64_t*>(slots + (index & slot_mask) * FOVEA_RING_SLOT_SIZE);
    }
    uint64_t* words_of(uint64_t index) const { return seq_of(index) + 1; }
};

inline std::size_t ring_bytes(uint32_t slot_count) {
    return sizeof(fovea_ring_header) + std::size_t{slot_count} * FOVEA_RING_SLOT_SIZE;
}

inline RingView make_view(void* base) {
    RingView v;
    v.header = static_cast<fovea_ring_header*>(base);
    v.slots = static_cast<unsigned char*>(base) + sizeof(fovea_ring_header);
    v.slot_mask = v.header->slot_count - 1;
    return v;
}

// Sequence values of record `index`: odd while being written, even once complete.
inline constexpr uint64_t seq_writing(uint64_t index) { return 2 * index + 1; }
inline constexpr uint64_t seq_done(uint64_t index) { return 2 * index + 2; }

// Data words are copied with relaxed atomics: a racing copy is then defined behaviour (and
// TSan-clean); the sequence check afterwards decides whether the copy is used.
inline void store_words(uint64_t* dst, const void* record) {
    uint64_t tmp[kRecordWords];
    std::memcpy(tmp, record, sizeof tmp);
    for (std::size_t i = 0; i < kRecordWords; ++i)
        __atomic_store_n(dst + i, tmp[i], __ATOMIC_RELAXED);
}

inline void load_words(const uint64_t* src, void* record) {
    uint64_t tmp[kRecordWords];
    for (std::size_t i = 0; i < kRecordWords; ++i)
        tmp[i] = __atomic_load_n(src + i, __ATOMIC_RELAXED);
    std::memcpy(record, tmp, sizeof tmp);
}

enum class SlotRead { kOk, kNotYet, kOverwritten };

// Copy record `index` out of the ring if it is complete and untorn.
inline SlotRead read_slot(const RingView& v, uint64_t index, void* out) {
    const uint64_t* seq = v.seq_of(index);
    const uint64_t want = seq_done(index);
    const uint64_t s1 = __atomic_load_n(seq, __ATOMIC_ACQUIRE);
    if (s1 < want) return SlotRead::kNotYet;  // being written, or still an older lap
    if (s1 > want) return SlotRead::kOverwritten;
    load_words(v.words_of(index), out);
    __atomic_thread_fence(__ATOMIC_ACQUIRE);
    const uint64_t s2 = __atomic_load_n(seq, __ATOMIC_RELAXED);
    return s2 == s1 ? SlotRead::kOk : SlotRead::kOverwritten;
}

}  // namespace fovea::ring
