// Finding where a JSON value starts in the source text, so that scene errors found after
// parsing (nlohmann keeps no positions) can still name a line. A small scanner over text
// that nlohmann has already accepted: it only has to track structure, not validate.
#include <string>

#include "host/scene.hpp"

namespace tp::host {

int line_of_offset(std::string_view text, std::size_t offset) {
  int line = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i)
    if (text[i] == '\n' || (text[i] == '\r' && (i + 1 == text.size() || text[i + 1] != '\n')))
      ++line;
  return line;
}

std::size_t start_of_line(std::string_view text, int line) {
  std::size_t at = 0;
  for (int l = 1; l < line && at < text.size(); ++l) {
    const std::size_t end = text.find_first_of("\r\n", at);
    if (end == std::string_view::npos) return text.size();
    at = end + (text.compare(end, 2, "\r\n") == 0 ? 2 : 1);
  }
  return at;
}

std::string json_pointer_token(std::string_view key) {
  std::string out;
  for (char c : key) {
    if (c == '~')
      out += "~0";
    else if (c == '/')
      out += "~1";
    else
      out += c;
  }
  return out;
}

std::size_t find_outside_strings(std::string_view text, std::string_view token) {
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;  // the escaped character cannot end the string
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (text.compare(i, token.size(), token) == 0) {
      return i;
    }
  }
  return std::string_view::npos;
}

namespace {

class Locator {
 public:
  Locator(std::string_view text, std::string_view target) : t_(text), target_(target) {}

  std::size_t find() {
    value("");
    return found_;
  }

 private:
  static constexpr std::size_t npos = std::string_view::npos;

  void ws() {
    while (i_ < t_.size() && (t_[i_] == ' ' || t_[i_] == '\t' || t_[i_] == '\n' || t_[i_] == '\r'))
      ++i_;
  }

  // Raw string contents (escapes kept verbatim except \" and \\, enough for key names).
  std::string str() {
    std::string s;
    ++i_;  // opening quote
    while (i_ < t_.size() && t_[i_] != '"') {
      if (t_[i_] == '\\' && i_ + 1 < t_.size()) ++i_;
      s += t_[i_++];
    }
    ++i_;  // closing quote
    return s;
  }

  // Stops as soon as the target is found: the rest of the text cannot change the answer.
  void value(const std::string& ptr) {
    ws();
    if (found_ == npos && ptr == target_) found_ = i_;
    if (found_ != npos || i_ >= t_.size()) return;
    const char c = t_[i_];
    if (c == '{') {
      ++i_;
      ws();
      while (found_ == npos && i_ < t_.size() && t_[i_] != '}') {
        const std::string key = str();
        ws();
        ++i_;  // ':'
        value(ptr + "/" + json_pointer_token(key));
        ws();
        if (i_ < t_.size() && t_[i_] == ',') ++i_;
        ws();
      }
      ++i_;
    } else if (c == '[') {
      ++i_;
      ws();
      for (int k = 0; found_ == npos && i_ < t_.size() && t_[i_] != ']'; ++k) {
        value(ptr + "/" + std::to_string(k));
        ws();
        if (i_ < t_.size() && t_[i_] == ',') ++i_;
        ws();
      }
      ++i_;
    } else if (c == '"') {
      str();
    } else {
      while (i_ < t_.size() && t_[i_] != ',' && t_[i_] != '}' && t_[i_] != ']' && t_[i_] != ' ' &&
             t_[i_] != '\n' && t_[i_] != '\r' && t_[i_] != '\t')
        ++i_;
    }
  }

  std::string_view t_;
  std::string_view target_;
  std::size_t i_ = 0;
  std::size_t found_ = npos;
};

}  // namespace

int line_of_pointer(std::string_view text, std::string_view pointer) {
  // A pointer to a missing key names its parent's line (the closest thing that exists). Each
  // step drops one reference token (keys are escaped, so a "/" in a key is not one), so the
  // steps are at most the document's depth, each one pass over the text at most.
  std::string p(pointer);
  while (true) {
    const std::size_t at = Locator(text, p).find();
    if (at != std::string_view::npos) return line_of_offset(text, at);
    if (p.empty()) return 0;
    p = p.substr(0, p.rfind('/'));
  }
}

}  // namespace tp::host
