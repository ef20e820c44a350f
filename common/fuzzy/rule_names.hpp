#pragma once
// An expert's words for a rule, apart from the numbers: the rule base itself never reads them.

#include <cstddef>
#include <string>
#include <vector>

namespace odonata::fuzzy {

/// An expert's words for one rule (a .fis's membership-function names), kept with the rule while
/// it lives — through refits that refine it, snapshots and model files — so an operator reads the
/// rules as the expert wrote them. Unnamed rules (the identifier's own) have none.
struct RuleNames {
  static constexpr std::size_t kMaxLength = 64;  ///< a longer name is refused (a hostile file)
  std::vector<std::string> terms;  ///< one per input ("" where unnamed or left out), or none
  std::string output;              ///< the rule's output term ("" unnamed)
  bool empty() const { return terms.empty() && output.empty(); }
  /// What is wrong with these names for a rule on `inputs` inputs ("" when nothing): terms must
  /// be none or one per input, each name at most kMaxLength printable characters.
  std::string Problem(int inputs) const {
    if (!terms.empty() && static_cast<int>(terms.size()) != inputs)
      return std::to_string(terms.size()) + " term names for " + std::to_string(inputs) + " inputs";
    const auto bad = [](const std::string& n) {
      if (n.size() > kMaxLength) return true;
      for (const char c : n)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return true;
      return false;
    };
    for (const auto& t : terms)
      if (bad(t)) return "a term name is longer than 64 characters or holds control characters";
    if (bad(output))
      return "the output term's name is longer than 64 characters or holds control characters";
    return "";
  }
  bool operator==(const RuleNames& o) const { return terms == o.terms && output == o.output; }
};

}  // namespace odonata::fuzzy
