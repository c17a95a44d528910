// The part of a scene file the loader holds in memory: JSON values as a flat array of entries with
// their strings in one pool, built by a streaming parser (scene/scene_stream.h). Flat and reused, so
// that reading a sphere allocates nothing; a value is a tree index (JsonValue).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace twinray::scene {

enum class JsonKind : std::uint8_t { null, boolean, signed_integer, unsigned_integer, floating, string, array, object };

class JsonTree;

// One value of a JsonTree (cheap to copy; valid while the tree keeps the value).
class JsonValue {
public:
    JsonValue(const JsonTree& tree, std::size_t index) : tree_(&tree), index_(index) {}

    JsonKind kind() const;
    bool is_object() const { return kind() == JsonKind::object; }
    bool is_array() const { return kind() == JsonKind::array; }
    bool is_string() const { return kind() == JsonKind::string; }
    bool is_number() const;
    bool is_boolean() const { return kind() == JsonKind::boolean; }
    bool boolean() const;

    // Arrays and objects: the number of elements or members.
    std::size_t size() const;
    // The first element or member; then each one's next_sibling. Only for i < size().
    JsonValue first_child() const { return {*tree_, index_ + 1}; }
    JsonValue next_sibling() const;
    // A member's key.
    std::string_view key() const;
    // An object's member named `key`.
    std::optional<JsonValue> find(std::string_view key) const;

    std::string_view string() const;
    // Any number as a double, as nlohmann's get<double> gives it (integers converted, -0 written as an
    // integer is +0).
    double number() const;
    // A scalar as nlohmann::json writes it ("2.0", "\"text\"", "true"), for messages.
    std::string dump() const;

    // An array of rows of three numbers held packed (JsonTree::Entry::rows): size() rows, read only through
    // row_number and row_dump (its rows have no entries to walk with first_child).
    bool is_packed_rows() const;
    // Column 0, 1 or 2 of a packed row: as number() and dump() give a number.
    double row_number(std::size_t row, std::size_t column) const;
    std::string row_dump(std::size_t row, std::size_t column) const;

private:
    const JsonTree* tree_;
    std::size_t index_;
};

class JsonTree {
public:
    struct Entry {
        JsonKind kind = JsonKind::null;
        bool boolean = false;
        std::size_t key_offset = 0, key_size = 0;    // in the pool, for a member of an object
        std::size_t text_offset = 0, text_size = 0;  // in the pool, for a string
        std::size_t end = 0;    // one past this value's last entry (containers: of their last descendant)
        std::size_t count = 0;  // containers: elements or members
        double number = 0;
        std::int64_t integer = 0;  // the exact value of an integer (an unsigned one bit for bit)
        // An array whose rows of three numbers are in the packed block from `text_offset` on, not entries of
        // their own: a mesh's vertices, triangles and normals (scene_stream.cpp), 9 bytes a number instead of
        // 72 and a row's entry.
        bool rows = false;
    };
    // Where the tree ends, to drop everything added after it (truncate).
    struct Mark {
        std::size_t entries = 0, pool_bytes = 0, packed = 0;
    };

    JsonValue root() const { return {*this, 0}; }
    std::size_t entry_count() const { return entries_.size(); }
    const Entry& entry(std::size_t index) const { return entries_[index]; }
    Entry& entry(std::size_t index) { return entries_[index]; }
    std::string_view pooled(std::size_t offset, std::size_t size) const { return {pool_.data() + offset, size}; }

    // Adds a value (with `key` if it is a member, given by pool offset and size); returns its index.
    std::size_t add(const Entry& entry) {
        entries_.push_back(entry);
        return entries_.size() - 1;
    }
    // Copies text into the pool; returns its offset.
    std::size_t pool(std::string_view text) {
        pool_.append(text);
        return pool_.size() - text.size();
    }
    // A number of a packed row (Entry::rows); integers only where a double holds them exactly.
    void pack(JsonKind kind, double number) {
        packed_kinds_.push_back(kind);
        packed_numbers_.push_back(number);
    }
    std::size_t packed_size() const { return packed_numbers_.size(); }
    double packed_number(std::size_t index) const { return packed_numbers_[index]; }
    // A packed number as the entry it was read as: an integer's exact value back from its double, a fraction's 0.
    Entry packed_entry(std::size_t index) const {
        Entry entry{.kind = packed_kinds_[index], .number = packed_numbers_[index]};
        if (entry.kind == JsonKind::signed_integer) {
            entry.integer = static_cast<std::int64_t>(entry.number);
        } else if (entry.kind == JsonKind::unsigned_integer) {
            entry.integer = static_cast<std::int64_t>(static_cast<std::uint64_t>(entry.number));
        }
        return entry;
    }

    Mark mark() const { return {entries_.size(), pool_.size(), packed_numbers_.size()}; }
    // Drops everything added after `mark`, keeping the capacity.
    void truncate(const Mark& mark) {
        entries_.resize(mark.entries);
        pool_.resize(mark.pool_bytes);
        packed_kinds_.resize(mark.packed);
        packed_numbers_.resize(mark.packed);
    }

private:
    std::vector<Entry> entries_;
    std::string pool_;
    std::vector<JsonKind> packed_kinds_;
    std::vector<double> packed_numbers_;
};

}  // namespace twinray::scene
