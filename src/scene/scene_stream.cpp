#include "scene/scene_stream.h"

#include "scene/refusal.h"

#include <rapidjson/error/en.h>
#include <rapidjson/filereadstream.h>
#include <rapidjson/memorystream.h>
#include <rapidjson/reader.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>
#include <string>
#include <system_error>
#include <vector>

namespace twinray::scene {
namespace {

using Entry = JsonTree::Entry;

constexpr std::string_view utf8_bom = "\xEF\xBB\xBF";

// Builds the tree from RapidJSON's events. A handler returning false stops the reader; the syntax
// error is then worded by nlohmann (check_syntax). The handler refuses what RapidJSON lets through
// and nlohmann does not: numbers beyond the range of double, and strings that are not well-formed
// UTF-8 (checked here rather than by RapidJSON's slower byte-by-byte validation).
class TreeBuilder : public rapidjson::BaseReaderHandler<rapidjson::UTF8<>, TreeBuilder> {
    // A mesh's rows being packed (JsonTree::Entry::rows): the array's entry, and the row being read.
    struct Packing {
        bool active = false;
        std::size_t array = 0;
        const char* row_noun = "";  // "triangle", "vertex" or "normal"
        bool row_open = false;
        int numbers_in_row = 0;
    };

public:
    TreeBuilder(JsonTree& tree, ObjectsReader& objects) : tree_(tree), objects_(objects) {}

    bool Null() { return scalar(Entry{}); }
    bool Bool(bool value) { return scalar(Entry{.kind = JsonKind::boolean, .boolean = value}); }
    bool RawNumber(const char* text, rapidjson::SizeType length, bool) {
        Entry entry;
        return parse_number(std::string_view(text, length), entry) && scalar(entry);
    }
    bool String(const char* text, rapidjson::SizeType length, bool) {
        const std::string_view value(text, length);
        if (!is_well_formed_utf8(value)) {
            return false;
        }
        Entry entry{.kind = JsonKind::string, .text_offset = tree_.pool(value), .text_size = value.size()};
        return scalar(entry);
    }
    bool StartObject() { return open(JsonKind::object); }
    bool StartArray() { return open(JsonKind::array); }
    bool EndObject(rapidjson::SizeType) { return close(); }
    bool EndArray(rapidjson::SizeType) { return close(); }

    bool Key(const char* text, rapidjson::SizeType length, bool) {
        const std::string_view key(text, length);
        if (!is_well_formed_utf8(key)) {
            return false;
        }
        Level& object = levels_.back();
        object.key_offset = tree_.pool(key);
        object.key_size = key.size();
        if (is_duplicate(object, key)) {
            refuse(path(), "duplicate key " + in_quotes(key) + "; a key may appear only once in an object");
        }
        return true;
    }

private:
    struct Level {
        std::size_t entry;
        std::size_t key_offset = 0, key_size = 0;  // objects: the last key read
        std::set<std::string, std::less<>> keys;   // objects of many members: their keys, for duplicates
    };

    // Integers as nlohmann reads them (int64 if negative, uint64 if not, a double beyond), numbers with a
    // fraction or exponent as the nearest double; false for one beyond the range of double.
    static bool parse_number(std::string_view text, Entry& entry) {
        const char* first = text.data();
        const char* last = first + text.size();
        const bool integral = text.find_first_of(".eE") == std::string_view::npos;
        if (integral && text.front() == '-' && std::from_chars(first, last, entry.integer).ec == std::errc{}) {
            entry.kind = JsonKind::signed_integer;
            entry.number = static_cast<double>(entry.integer);
            return true;
        }
        std::uint64_t unsigned_value = 0;
        if (integral && text.front() != '-' && std::from_chars(first, last, unsigned_value).ec == std::errc{}) {
            entry.kind = JsonKind::unsigned_integer;
            entry.integer = static_cast<std::int64_t>(unsigned_value);
            entry.number = static_cast<double>(unsigned_value);
            return true;
        }
        entry.kind = JsonKind::floating;
        if (std::from_chars(first, last, entry.number).ec != std::errc{}) {
            // Out of range: strtod, as nlohmann, gives the denormal or zero of an underflow.
            entry.number = std::strtod(std::string(text).c_str(), nullptr);
        }
        return std::isfinite(entry.number);
    }

    // Well-formed UTF-8 as nlohmann requires it (Unicode's table 3-7: no overlong forms, no surrogates,
    // nothing beyond U+10FFFF). Checked on the decoded text, where RapidJSON copies raw bytes as they
    // are and writes a lone surrogate escape (\uDC00) as the ill-formed bytes ED B0 80.
    static bool is_well_formed_utf8(std::string_view text) {
        const auto byte = [&text](std::size_t at) { return static_cast<unsigned char>(text[at]); };
        for (std::size_t at = 0; at < text.size();) {
            const unsigned char lead = byte(at);
            if (lead < 0x80) {
                ++at;
                continue;
            }
            std::size_t length = 3;
            unsigned char second_low = 0x80, second_high = 0xBF;
            if (lead >= 0xC2 && lead <= 0xDF) {
                length = 2;
            } else if (lead == 0xE0) {
                second_low = 0xA0;
            } else if (lead == 0xED) {
                second_high = 0x9F;
            } else if (lead >= 0xF0 && lead <= 0xF4) {
                length = 4;
                second_low = lead == 0xF0 ? 0x90 : 0x80;
                second_high = lead == 0xF4 ? 0x8F : 0xBF;
            } else if (lead < 0xE1 || lead > 0xEF) {
                return false;
            }
            if (text.size() - at < length || byte(at + 1) < second_low || byte(at + 1) > second_high) {
                return false;
            }
            for (std::size_t k = 2; k < length; ++k) {
                if ((byte(at + k) & 0xC0) != 0x80) {
                    return false;
                }
            }
            at += length;
        }
        return true;
    }

    bool is_duplicate(Level& object, std::string_view key) {
        constexpr std::size_t compared_one_by_one = 64;
        const std::size_t members = tree_.entry(object.entry).count;
        if (members < compared_one_by_one) {
            JsonValue member = JsonValue(tree_, object.entry).first_child();
            for (std::size_t i = 0; i < members; ++i, member = member.next_sibling()) {
                if (member.key() == key) {
                    return true;
                }
            }
            return false;
        }
        if (object.keys.empty()) {
            JsonValue member = JsonValue(tree_, object.entry).first_child();
            for (std::size_t i = 0; i < members; ++i, member = member.next_sibling()) {
                object.keys.emplace(member.key());
            }
        }
        return !object.keys.emplace(key).second;
    }

    // Adds a value to the open container, as a member under the last key or as an element.
    std::size_t add(Entry entry) {
        if (!levels_.empty()) {
            Level& parent = levels_.back();
            if (tree_.entry(parent.entry).kind == JsonKind::object) {
                entry.key_offset = parent.key_offset;
                entry.key_size = parent.key_size;
            } else if (is_streamed_array(parent)) {
                element_start_ = tree_.mark();
            } else if (is_kept_objects_array(parent) && tree_.entry(parent.entry).count == objects_.most_elements()) {
                const std::size_t count = tree_.entry(parent.entry).count;
                refuse(index_path("objects", count),
                       over_primitive_limit("element number " + std::to_string(count + 1) +
                                                " of objects, each holding a primitive at least",
                                            count));
            }
            ++tree_.entry(parent.entry).count;
        }
        return tree_.add(entry);
    }

    bool scalar(const Entry& entry) {
        if (packing_.active) {
            if (packing_.row_open && packing_.numbers_in_row < 3 && is_packable(entry)) {
                tree_.pack(entry.kind, entry.number);
                ++packing_.numbers_in_row;
                return true;
            }
            unpack();
        }
        const std::size_t index = add(entry);
        tree_.entry(index).end = index + 1;
        completed(index);
        return true;
    }

    bool open(JsonKind kind) {
        if (packing_.active) {
            if (kind == JsonKind::array && !packing_.row_open) {
                packing_.row_open = true;
                packing_.numbers_in_row = 0;
                return true;
            }
            unpack();
        }
        const bool rows = kind == JsonKind::array && is_mesh_rows_key();
        const std::string_view key = rows ? last_key() : "";
        const std::size_t index = add(Entry{.kind = kind});
        if (levels_.size() == max_json_depth) {
            refuse(path(), "nested deeper than " + std::to_string(max_json_depth) +
                               " levels of arrays and objects, the most a scene may use");
        }
        if (kind == JsonKind::array && levels_.size() == 1 && is_root_member("objects")) {
            streamed_array_ = index;
            streaming_ = objects_.stream_elements(tree_);
        }
        levels_.push_back(Level{index, 0, 0, {}});
        if (rows) {
            tree_.entry(index).text_offset = tree_.packed_size();
            packing_ = Packing{.active = true,
                               .array = index,
                               .row_noun = key == "triangles"  ? "triangle"
                                           : key == "vertices" ? "vertex"
                                                               : "normal"};
        }
        return true;
    }

    bool close() {
        if (packing_.active) {
            if (packing_.row_open && packing_.numbers_in_row == 3) {
                packing_.row_open = false;
                ++tree_.entry(packing_.array).count;
                refuse_rows_past_the_limit();
                return true;
            }
            if (!packing_.row_open) {
                tree_.entry(packing_.array).rows = true;
                packing_.active = false;
            } else {
                unpack();
            }
        }
        const std::size_t index = levels_.back().entry;
        levels_.pop_back();
        tree_.entry(index).end = tree_.entry_count();
        completed(index);
        return true;
    }

    bool is_root_member(std::string_view key) const {
        const Level& root = levels_.front();
        return tree_.entry(root.entry).kind == JsonKind::object && tree_.pooled(root.key_offset, root.key_size) == key;
    }

    bool is_streamed_array(const Level& level) const {
        return streaming_ && levels_.size() == 2 && level.entry == streamed_array_;
    }
    // The root's "objects" array when its elements stay in the tree (materials come after it).
    bool is_kept_objects_array(const Level& level) const {
        return !streaming_ && levels_.size() == 2 && streamed_array_ != 0 && level.entry == streamed_array_;
    }

    // An element of the streamed array is handed over, then dropped with everything it pooled.
    void completed(std::size_t index) {
        if (!levels_.empty() && is_streamed_array(levels_.back())) {
            objects_.element(JsonValue(tree_, streamed_array_), JsonValue(tree_, index),
                             tree_.entry(streamed_array_).count - 1);
            tree_.truncate(element_start_);
        }
    }

    // A top-level object's "vertices", "triangles" or "normals": a mesh's rows, packed while each is three numbers.
    bool is_mesh_rows_key() const {
        if (levels_.size() != 3 || streamed_array_ == 0 || levels_[1].entry != streamed_array_) {
            return false;
        }
        if (tree_.entry(levels_[2].entry).kind != JsonKind::object) {
            return false;
        }
        const std::string_view key = last_key();
        return key == "vertices" || key == "triangles" || key == "normals";
    }

    // The last key read in the innermost open object.
    std::string_view last_key() const { return tree_.pooled(levels_.back().key_offset, levels_.back().key_size); }

    // A mesh holds at most a triangle per primitive of the limit, and three vertices and normals per triangle
    // (as a mesh file may): refused at the row past that as it is read, so that no text grows the packed rows
    // beyond what a mesh at the limit holds.
    void refuse_rows_past_the_limit() const {
        const std::size_t rows = tree_.entry(packing_.array).count;
        const std::size_t limit = objects_.most_elements();
        const bool triangles = std::string_view(packing_.row_noun) == "triangle";
        if (rows > (triangles ? limit : 3 * limit)) {
            const std::string row = packing_.row_noun + std::string(" number ") + std::to_string(rows) + " of a mesh";
            refuse(path(), triangles ? over_primitive_limit(row, limit)
                                     : row + ": more than three per triangle of the limit of " + std::to_string(limit) +
                                           " primitives");
        }
    }

    // A number whose kind and value a packed row keeps exactly: any double, an integer up to 2^53.
    static bool is_packable(const Entry& entry) {
        constexpr std::int64_t exact = std::int64_t{1} << 53;
        switch (entry.kind) {
            case JsonKind::floating: return true;
            case JsonKind::signed_integer: return entry.integer >= -exact;
            case JsonKind::unsigned_integer: return static_cast<std::uint64_t>(entry.integer) <= exact;
            default: return false;
        }
    }

    // Something other than a row of three numbers: the rows packed so far become entries, as if never packed
    // (a row cut short stays open), and the event that found it is read as usual, so every message stays as it
    // was.
    void unpack() {
        const std::size_t array = packing_.array;
        const std::size_t first = tree_.entry(array).text_offset;
        const std::size_t rows = tree_.entry(array).count;
        const bool row_open = packing_.row_open;
        std::vector<Entry> numbers;
        for (std::size_t at = first; at < tree_.packed_size(); ++at) {
            numbers.push_back(tree_.packed_entry(at));
        }
        JsonTree::Mark before = tree_.mark();
        before.packed = first;
        tree_.truncate(before);
        tree_.entry(array).count = 0;
        tree_.entry(array).text_offset = 0;
        packing_ = Packing{};
        for (std::size_t row = 0; row < rows + (row_open ? 1 : 0); ++row) {
            open(JsonKind::array);
            for (std::size_t column = 0; column < 3 && 3 * row + column < numbers.size(); ++column) {
                scalar(numbers[3 * row + column]);
            }
            if (row < rows) {
                close();
            }
        }
    }

    // The path of the value being read (the last key or element of each open level).
    std::string path() const {
        std::string result;
        for (const Level& level : levels_) {
            const Entry& entry = tree_.entry(level.entry);
            result = entry.kind == JsonKind::object ? key_path(result, tree_.pooled(level.key_offset, level.key_size))
                                                    : index_path(result, entry.count - 1);
        }
        return result;
    }

    JsonTree& tree_;
    ObjectsReader& objects_;
    std::vector<Level> levels_;
    std::size_t streamed_array_ = 0;
    bool streaming_ = false;
    JsonTree::Mark element_start_;
    Packing packing_;
};

// ---------------------------------------------------------------------------------------------------
// Syntax errors in nlohmann's words, with line and column.

std::string line_and_column(std::string_view text, std::size_t bytes_read) {
    // The parser counts the character it stopped at as read; at the end of the input that is one past
    // the last byte. Columns count bytes, not characters.
    const std::size_t offset = std::min(bytes_read == 0 ? 0 : bytes_read - 1, text.size());
    const std::string_view before = text.substr(0, offset);
    const auto line = 1 + std::count(before.begin(), before.end(), '\n');
    const std::size_t last_newline = before.rfind('\n');
    const std::size_t line_start = last_newline == std::string_view::npos ? 0 : last_newline + 1;
    return "line " + std::to_string(line) + ", column " + std::to_string(offset - line_start + 1);
}

// The parser quotes the bytes it stopped at, which may not be UTF-8; a message must stay printable.
std::string ascii_only(std::string_view text) {
    static constexpr char hex[] = "0123456789ABCDEF";
    std::string result;
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        result += byte < 0x80 ? std::string(1, c) : std::string{'\\', 'x', hex[byte >> 4], hex[byte & 15]};
    }
    return result;
}

// What follows the first `marker` in `text`, or all of `text` if there is none.
std::string_view after(std::string_view text, std::string_view marker) {
    const std::size_t found = text.find(marker);
    return found == std::string_view::npos ? text : text.substr(found + marker.size());
}

// "[json.exception.parse_error.101] parse error at line 1, column 5: syntax error ..." keeps only
// "syntax error ...": the position is reported separately, computed from the byte offset.
std::string plain_parser_message(const nlohmann::json::exception& error) {
    std::string_view message = after(error.what(), "] ");
    if (message.starts_with("parse error")) {
        message = after(message, ": ");
    }
    // The parser's one refusal that is not a syntax error (406): a number beyond the range of double.
    const std::string allowed =
        error.id == 406
            ? "; numbers must be finite, at most " + format_number(std::numeric_limits<double>::max()) + " in magnitude"
            : "";
    return ascii_only(message) + allowed;
}

// Accepts every value; refuses at nlohmann's first syntax error.
class SyntaxCheck final : public nlohmann::json_sax<nlohmann::json> {
public:
    explicit SyntaxCheck(std::string_view text) : text_(text) {}

    bool null() override { return true; }
    bool boolean(bool) override { return true; }
    bool number_integer(number_integer_t) override { return true; }
    bool number_unsigned(number_unsigned_t) override { return true; }
    bool number_float(number_float_t, const string_t&) override { return true; }
    bool string(string_t&) override { return true; }
    bool binary(binary_t&) override { return true; }
    bool start_object(std::size_t) override { return true; }
    bool start_array(std::size_t) override { return true; }
    bool end_object() override { return true; }
    bool end_array() override { return true; }
    bool key(string_t&) override { return true; }

    bool parse_error(std::size_t bytes_read, const std::string&, const nlohmann::json::exception& error) override {
        throw Refusal{line_and_column(text_, bytes_read), plain_parser_message(error)};
    }

private:
    std::string_view text_;
};

// Asked where RapidJSON stopped early or before the end of the input: nlohmann's words for the
// syntax error. RapidJSON's own words if nlohmann finds none, which would be a difference between
// the two parsers (the fuzz target would catch it). Both read a NUL byte as the end of the input, so a
// document followed by a NUL and anything is accepted, as it always was.
void check_syntax(std::string_view text, const rapidjson::ParseResult& result) {
    SyntaxCheck check(text);
    static_cast<void>(nlohmann::json::sax_parse(text.begin(), text.end(), &check));
    if (result.IsError()) {
        throw Refusal{line_and_column(text, result.Offset() + 1), rapidjson::GetParseError_En(result.Code())};
    }
}

constexpr unsigned reader_flags = rapidjson::kParseNumbersAsStringsFlag;

}  // namespace

void read_json(std::string_view text, JsonTree& tree, ObjectsReader& objects) {
    // nlohmann skips a byte order mark; RapidJSON would stop at it.
    const std::size_t start = text.starts_with(utf8_bom) ? utf8_bom.size() : 0;
    rapidjson::MemoryStream stream(text.data() + start, text.size() - start);
    TreeBuilder builder(tree, objects);
    rapidjson::Reader reader;
    const rapidjson::ParseResult result = reader.Parse<reader_flags>(stream, builder);
    if (result.IsError() || start + stream.Tell() != text.size()) {
        check_syntax(text, result);
    }
}

void read_json(std::FILE* file, JsonTree& tree, ObjectsReader& objects) {
    char bom[3] = {};
    const bool has_bom = std::fread(bom, 1, sizeof bom, file) == sizeof bom && std::string_view(bom, 3) == utf8_bom;
    if (!has_bom) {
        std::rewind(file);
    }
    char buffer[65536];
    rapidjson::FileReadStream stream(file, buffer, sizeof buffer);
    TreeBuilder builder(tree, objects);
    rapidjson::Reader reader;
    const rapidjson::ParseResult result = reader.Parse<reader_flags>(stream, builder);
    if (std::ferror(file)) {
        throw std::system_error(errno, std::generic_category());
    }
    const bool read_to_the_end = !result.IsError() && std::feof(file) && stream.Peek() == '\0' &&
                                 static_cast<long>(stream.Tell() + (has_bom ? 3 : 0)) == std::ftell(file);
    if (!read_to_the_end) {
        // Rare: the text again, for nlohmann to find and word the error, up to where RapidJSON stopped (its
        // error, or a NUL byte, where both parsers end) and a margin for the token there, not to the end:
        // a broken file of gigabytes is refused without holding it.
        constexpr std::size_t margin = 65536;
        const std::size_t stopped = (result.IsError() ? result.Offset() : stream.Tell()) + (has_bom ? 3 : 0);
        std::rewind(file);
        std::string text;
        while (text.size() <= stopped + margin) {
            const std::size_t count = std::fread(buffer, 1, sizeof buffer, file);
            if (count == 0) {
                break;
            }
            text.append(buffer, count);
        }
        check_syntax(text, result);
    }
}

}  // namespace twinray::scene
