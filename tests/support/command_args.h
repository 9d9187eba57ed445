#pragma once
// An argv for parsing a command line in a test: the program's name, then the arguments, as main() receives them.

#include <string>
#include <utility>
#include <vector>

namespace poet::testing {

class CommandArgs {
 public:
  CommandArgs(std::string program, std::vector<std::string> args) : strings_(std::move(args)) {
    strings_.insert(strings_.begin(), std::move(program));
    for (std::string& s : strings_) argv_.push_back(s.data());
    argv_.push_back(nullptr);
  }
  int argc() const { return static_cast<int>(strings_.size()); }
  char** argv() { return argv_.data(); }

 private:
  std::vector<std::string> strings_;
  std::vector<char*> argv_;
};

}  // namespace poet::testing
