#pragma once
// Which slot holds each mesh of a dynrt::Engine. A slot is an index into the engine's scene
// objects, per-object states and trees (FramePipeline, SceneAccel), so hits name slots; a
// MeshId is what the caller holds. Ids are never reused (a stale id is refused, never taken
// for another mesh), while slots are: a removed mesh's slot goes free once an update has
// dropped its tree, and the next add_mesh takes it, so a simulation that adds and removes
// meshes forever keeps as many slots as it ever had meshes at once (plus those removed since
// the last update), not one per mesh it ever added.
//
// Life of a slot: taken (claim) -> its id retired by remove_mesh (the id is refused from then
// on, but the trees of the last update still hit the slot, and report the old id) -> freed
// (free) once an update no longer shows it -> taken again.

#include "update/held_bytes.h"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

namespace dynrt::api_detail {

class MeshSlots {
public:
    /// A mesh's id and the slot it holds.
    struct Claim {
        std::uint32_t id = 0;
        std::size_t slot = 0;
        /// The slot was freed by another mesh (false: a new slot at the end).
        bool reused = false;
    };

    /// The ids issued run out before MeshId's "no mesh" value and before the image's int32
    /// mesh buffer (ImageView::mesh) can no longer hold them.
    static constexpr std::uint32_t kMaxIds = std::uint32_t(std::numeric_limits<std::int32_t>::max());

    /// The id the next claim() issues.
    std::uint32_t next_id() const { return next_id_; }
    /// Whether another id can be issued.
    bool can_claim() const { return next_id_ < kMaxIds; }

    /// A new id, in a free slot when there is one (the one freed last: its memory is the
    /// warmest), else in a new slot at the end. Precondition: can_claim().
    Claim claim() {
        Claim c;
        c.id = next_id_++;
        if (free_.empty()) {
            c.slot = id_of_slot_.size();
            id_of_slot_.push_back(c.id);
        } else {
            c.slot = free_.back();
            free_.pop_back();
            c.reused = true;
            id_of_slot_[c.slot] = c.id;
        }
        if (c.id != c.slot) ids_are_slots_ = false;
        slot_of_id_[c.id] = std::uint32_t(c.slot);
        return c;
    }

    /// The slot of a live id (claimed, not retired), or nothing.
    std::optional<std::size_t> slot_of(std::uint32_t id) const {
        const auto found = slot_of_id_.find(id);
        if (found == slot_of_id_.end()) return std::nullopt;
        return found->second;
    }
    /// Whether `id` was issued (live, or retired since).
    bool issued(std::uint32_t id) const { return id < next_id_; }

    /// The id the slot's hits report: its mesh's, until another mesh claims the slot.
    std::uint32_t id_at(std::size_t slot) const { return id_of_slot_[slot]; }
    /// Whether every slot's id is the slot itself (no slot was ever reused), so hits need no
    /// translation.
    bool ids_are_slots() const { return ids_are_slots_; }
    /// The id of each slot, for translating hits as they are written; empty while
    /// ids_are_slots().
    std::span<const std::uint32_t> ids_of_slots() const {
        return ids_are_slots_ ? std::span<const std::uint32_t>{} : std::span<const std::uint32_t>(id_of_slot_);
    }

    /// remove_mesh: the id is refused from now on; its slot still reports it.
    void retire(std::uint32_t id) { slot_of_id_.erase(id); }
    /// The slot may be claimed again: its retired mesh is in no tree any more.
    void free(std::size_t slot) { free_.push_back(slot); }

    /// Slots ever used (live, retired and free).
    std::size_t slots() const { return id_of_slot_.size(); }

    /// Heap bytes held (the hash map's nodes estimated as a key, a value and two pointers).
    std::size_t memory_bytes() const {
        return held_bytes(id_of_slot_) + held_bytes(free_) +
               slot_of_id_.bucket_count() * sizeof(void*) +
               slot_of_id_.size() * (2 * sizeof(std::uint32_t) + 2 * sizeof(void*));
    }

private:
    std::uint32_t next_id_ = 0;
    std::vector<std::uint32_t> id_of_slot_;
    std::vector<std::size_t> free_;
    std::unordered_map<std::uint32_t, std::uint32_t> slot_of_id_;
    bool ids_are_slots_ = true;
};

}  // namespace dynrt::api_detail
