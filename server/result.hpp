// Success, or why not in words: the outcome of validating or applying a control message, whose
// message becomes the text of the client's error reply. It replaces an empty string meaning
// success, where a failure whose message was forgotten read as success.
#pragma once
#include <string>
#include <utility>

namespace tp::server {

class [[nodiscard]] Result {
 public:
  static Result success() { return Result(); }
  // why must say what is wrong (it is shown to the user as is).
  static Result failure(std::string why) { return Result(std::move(why)); }

  bool ok() const { return ok_; }
  const std::string& message() const { return message_; }  // empty when ok()

 private:
  Result() = default;
  explicit Result(std::string why) : ok_(false), message_(std::move(why)) {}

  bool ok_ = true;
  std::string message_;
};

}  // namespace tp::server
