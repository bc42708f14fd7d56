// A per-thread bump allocator for objects that live for one path sample (BSDFs at the hits of a
// path). Reset after each sample; nothing allocated here is destroyed, so only trivially
// destructible types belong in it.
#pragma once

#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace ml {

class ScratchBuffer {
public:
    explicit ScratchBuffer(size_t bytes = 64 * 1024) : m_size(bytes) {
        m_data.reset(new std::byte[m_size]);
    }
    template <typename T, typename... Args>
    T* alloc(Args&&... args) {
        static_assert(std::is_trivially_destructible_v<T>, "scratch objects are never destroyed");
        void* p = allocate(sizeof(T), alignof(T));
        return new (p) T(std::forward<Args>(args)...);
    }
    void reset() {
        m_offset = 0;
        m_overflow.clear();
    }

private:
    void* allocate(size_t size, size_t align) {
        size_t start = (m_offset + align - 1) & ~(align - 1);
        if (start + size > m_size) {
            // Rare: more than fits in one sample; fall back to the heap until the next reset.
            m_overflow.emplace_back(new std::byte[size + align]);
            void* p = m_overflow.back().get();
            size_t space = size + align;
            return std::align(align, size, p, space);
        }
        m_offset = start + size;
        return m_data.get() + start;
    }
    std::unique_ptr<std::byte[]> m_data;
    size_t m_size;
    size_t m_offset = 0;
    std::vector<std::unique_ptr<std::byte[]>> m_overflow;
};

}  // namespace ml
