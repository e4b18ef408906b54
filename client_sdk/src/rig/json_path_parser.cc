#include "rig/json_path_parser.h"

#include <vector>

namespace omnisweep::json_detail {
namespace {

using nlohmann::json;

class PathTrackingSax {
 public:
  explicit PathTrackingSax(json* root) : root_(root) {}

  bool null() { return add(nullptr); }
  bool boolean(bool v) { return add(v); }
  bool number_integer(json::number_integer_t v) { return add(v); }
  bool number_unsigned(json::number_unsigned_t v) { return add(v); }
  bool number_float(json::number_float_t v, const std::string&) { return add(v); }
  bool string(std::string& v) { return add(std::move(v)); }
  bool binary(json::binary_t& v) { return add(json::binary(std::move(v))); }
  bool start_object(std::size_t) { return open(json::object()); }
  bool key(std::string& k) {
    keys_.back() = k;
    return true;
  }
  bool end_object() { return close(); }
  bool start_array(std::size_t) { return open(json::array()); }
  bool end_array() { return close(); }
  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) {
    error_position_ = position;
    error_message_ = e.what();
    error_path_ = current_path();
    return false;
  }

  std::size_t error_position() const { return error_position_; }
  const std::string& error_message() const { return error_message_; }
  const std::string& error_path() const { return error_path_; }

 private:
  json* slot(json value) {
    if (stack_.empty()) {
      *root_ = std::move(value);
      return root_;
    }
    json& parent = *stack_.back();
    if (parent.is_array()) {
      parent.push_back(std::move(value));
      return &parent.back();
    }
    json& member = parent[keys_.back()];
    member = std::move(value);
    return &member;
  }
  bool add(json value) {
    slot(std::move(value));
    return true;
  }
  bool open(json container) {
    stack_.push_back(slot(std::move(container)));
    keys_.emplace_back();
    return true;
  }
  bool close() {
    stack_.pop_back();
    keys_.pop_back();
    return true;
  }
  std::string current_path() const {
    std::string path;
    for (std::size_t i = 0; i < stack_.size(); ++i) {
      if (stack_[i]->is_array()) {
        // An element being parsed inside a nested container has already been appended.
        const std::size_t size = stack_[i]->size();
        path = index_path(path, i + 1 < stack_.size() ? size - 1 : size);
      } else if (!keys_[i].empty()) {
        path = join_path(path, keys_[i]);
      }
    }
    return path;
  }

  json* root_;
  std::vector<json*> stack_;
  std::vector<std::string> keys_;
  std::size_t error_position_ = 0;
  std::string error_message_;
  std::string error_path_;
};

// Drops nlohmann's "[json.exception.parse_error.101] parse error at line 3, column 7: " lead-in;
// our message gives the position itself (also for errors where nlohmann gives none).
std::string strip_exception_prefix(std::string what) {
  if (!what.empty() && what.front() == '[') {
    const auto end = what.find("] ");
    if (end != std::string::npos) what = what.substr(end + 2);
  }
  if (what.rfind("parse error", 0) == 0) {
    const auto colon = what.find(": ");
    if (colon != std::string::npos) what = what.substr(colon + 2);
  }
  return what;
}

}  // namespace

bool parse_with_path(std::string_view text, nlohmann::json* out, ParseFailure* failure) {
  PathTrackingSax sax(out);
  if (nlohmann::json::sax_parse(text, &sax, nlohmann::json::input_format_t::json, true, false)) {
    return true;
  }
  const std::size_t pos = std::min(sax.error_position(), text.size());
  failure->path = sax.error_path();
  failure->line = 1;
  failure->column = 0;  // becomes the 1-based column of the last character read
  for (std::size_t i = 0; i < pos; ++i) {
    if (text[i] == '\n') {
      ++failure->line;
      failure->column = 0;
    } else {
      ++failure->column;
    }
  }
  failure->message = strip_exception_prefix(sax.error_message());
  return false;
}

std::string join_path(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

std::string index_path(const std::string& parent, std::size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

}  // namespace omnisweep::json_detail
