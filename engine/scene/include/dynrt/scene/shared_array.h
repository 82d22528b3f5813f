#pragma once
// An array whose copies share one block of elements until one of them is written: the storage
// of a Mesh, so that many objects can hold the same mesh (a glTF mesh that several nodes
// reference, a procedural forest of one tree) for the bytes of a pointer each, and the engine
// can tell that two objects hold the same triangles by the address of their storage.
//
// Copy-on-write, as Qt's implicitly shared containers: reads go straight to the shared block;
// every writing member first makes the array's own copy when the block is shared. Only writing
// members hand out mutable access (there is no mutable operator[] or begin()), so a read can
// never copy a block by accident, and a reference from edit() must not be kept across a later
// copy of the array (the copy would see its writes).

#include <cstddef>
#include <initializer_list>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace dynrt {

template <typename T>
class SharedArray {
public:
    using value_type = T;
    using size_type = std::size_t;
    using const_iterator = const T*;
    using iterator = const T*;

    SharedArray() = default;
    SharedArray(std::vector<T> elements)  // NOLINT: implicit, as the vector it replaces
        : block_(elements.empty() ? nullptr : std::make_shared<std::vector<T>>(std::move(elements))) {}
    SharedArray(std::initializer_list<T> elements) : SharedArray(std::vector<T>(elements)) {}
    template <typename It>
    SharedArray(It first, It last) : SharedArray(std::vector<T>(first, last)) {}

    SharedArray& operator=(std::vector<T> elements) { return *this = SharedArray(std::move(elements)); }
    SharedArray& operator=(std::initializer_list<T> elements) { return *this = SharedArray(elements); }

    // Reading: never copies.
    std::size_t size() const { return block_ ? block_->size() : 0; }
    bool empty() const { return size() == 0; }
    const T* data() const { return block_ ? block_->data() : nullptr; }
    const T& operator[](std::size_t i) const { return (*block_)[i]; }
    const T* begin() const { return data(); }
    const T* end() const { return data() + size(); }
    const T& at(std::size_t i) const { return vector().at(i); }
    const T& front() const { return block_->front(); }
    const T& back() const { return block_->back(); }
    std::size_t capacity() const { return block_ ? block_->capacity() : 0; }
    /// The elements as a vector (an empty one when there are none).
    const std::vector<T>& vector() const { return block_ ? *block_ : empty_vector(); }
    operator const std::vector<T>&() const { return vector(); }  // NOLINT: reads as the vector did
    operator std::span<const T>() const { return {data(), size()}; }  // NOLINT

    /// Whether `other` holds this very block (not merely equal elements).
    bool shares_storage_with(const SharedArray& other) const { return block_ && block_ == other.block_; }
    /// How many arrays hold this block (0 when empty): heap bytes are counted once per block.
    long holders() const { return block_ ? block_.use_count() : 0; }

    friend bool operator==(const SharedArray& a, const SharedArray& b) { return a.vector() == b.vector(); }

    // Writing: the array's own copy first, when the block is shared.
    /// The elements to write; a copy of the block when another array holds it too. Do not
    /// keep the reference across a copy of this array.
    std::vector<T>& edit() {
        if (!block_) {
            block_ = std::make_shared<std::vector<T>>();
        } else if (block_.use_count() > 1) {
            block_ = std::make_shared<std::vector<T>>(*block_);
        }
        return *block_;
    }
    void push_back(const T& value) { edit().push_back(value); }
    template <typename... Args>
    T& emplace_back(Args&&... args) { return edit().emplace_back(std::forward<Args>(args)...); }
    void resize(std::size_t n) { edit().resize(n); }
    void reserve(std::size_t n) { edit().reserve(n); }
    template <typename It>
    void assign(It first, It last) { edit().assign(first, last); }
    /// Inserts [first, last) before `position` (an address from begin() .. end()).
    template <typename It>
    void insert(const T* position, It first, It last) {
        const std::ptrdiff_t at = position - data();
        std::vector<T>& elements = edit();
        elements.insert(elements.begin() + at, first, last);
    }
    void insert(const T* position, std::initializer_list<T> values) {
        insert(position, values.begin(), values.end());
    }
    /// Lets go of the block (freeing it when no other array holds it).
    void clear() { block_.reset(); }

private:
    static const std::vector<T>& empty_vector() {
        static const std::vector<T> none;
        return none;
    }
    std::shared_ptr<std::vector<T>> block_;
};

}  // namespace dynrt
