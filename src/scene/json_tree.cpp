#include "scene/json_tree.h"

#include <nlohmann/json.hpp>

namespace twinray::scene {

JsonKind JsonValue::kind() const {
    return tree_->entry(index_).kind;
}

bool JsonValue::boolean() const {
    return tree_->entry(index_).boolean;
}

bool JsonValue::is_number() const {
    const JsonKind k = kind();
    return k == JsonKind::signed_integer || k == JsonKind::unsigned_integer || k == JsonKind::floating;
}

std::size_t JsonValue::size() const {
    return tree_->entry(index_).count;
}

JsonValue JsonValue::next_sibling() const {
    return {*tree_, tree_->entry(index_).end};
}

std::string_view JsonValue::key() const {
    const JsonTree::Entry& entry = tree_->entry(index_);
    return tree_->pooled(entry.key_offset, entry.key_size);
}

std::optional<JsonValue> JsonValue::find(std::string_view name) const {
    JsonValue member = first_child();
    for (std::size_t i = 0; i < size(); ++i, member = member.next_sibling()) {
        if (member.key() == name) {
            return member;
        }
    }
    return std::nullopt;
}

std::string_view JsonValue::string() const {
    const JsonTree::Entry& entry = tree_->entry(index_);
    return tree_->pooled(entry.text_offset, entry.text_size);
}

double JsonValue::number() const {
    return tree_->entry(index_).number;
}

namespace {

// A scalar as nlohmann::json writes it; `text` is a string's.
std::string dump_scalar(const JsonTree::Entry& entry, std::string_view text) {
    switch (entry.kind) {
        case JsonKind::boolean: return nlohmann::json(entry.boolean).dump();
        case JsonKind::signed_integer: return nlohmann::json(entry.integer).dump();
        case JsonKind::unsigned_integer: return nlohmann::json(static_cast<std::uint64_t>(entry.integer)).dump();
        case JsonKind::floating: return nlohmann::json(entry.number).dump();
        case JsonKind::string: return nlohmann::json(std::string(text)).dump();
        case JsonKind::null:
        case JsonKind::array:
        case JsonKind::object: break;
    }
    return "null";
}

}  // namespace

std::string JsonValue::dump() const {
    const JsonTree::Entry& entry = tree_->entry(index_);
    return dump_scalar(entry, entry.kind == JsonKind::string ? string() : std::string_view());
}

bool JsonValue::is_packed_rows() const {
    return tree_->entry(index_).rows;
}

double JsonValue::row_number(std::size_t row, std::size_t column) const {
    return tree_->packed_number(tree_->entry(index_).text_offset + 3 * row + column);
}

std::string JsonValue::row_dump(std::size_t row, std::size_t column) const {
    return dump_scalar(tree_->packed_entry(tree_->entry(index_).text_offset + 3 * row + column), "");
}

}  // namespace twinray::scene
