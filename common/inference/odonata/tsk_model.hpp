#pragma once
// Run an odonata model in flight code: a header-only, first-order (or zero-order) Takagi–Sugeno
// model in raw units, read from the `.fis` file `odonata-export` writes. No LCM, no Eigen, no
// allocation in Evaluate(): copy this one file into the vehicle's source tree.
//
//   std::ifstream in("roll.fis");
//   const auto model = odonata::inference::TskModel::FromFis(in);  // throws on a bad file
//   const double x[] = {p_k, p_k_1, u_k};  // in the order of the file's [InputN] sections
//   const double y = model.Evaluate(x, 3);
//
// What it computes (docs/model_export.md §1): for rule j with Gaussian memberships
// μ_ji(x_i) = exp(−(x_i − c_ji)² / (2 σ_ji²)), firing w_j = weight_j · Π_i μ_ji(x_i), rule
// output y_j = a_j0 + Σ_i a_ji x_i (or the constant a_j0), and
// ŷ = Σ_j w_j y_j / Σ_j w_j — MATLAB's and Octave's `evalfis` of a Sugeno system with
// AndMethod 'prod' and DefuzzMethod 'wtaver'. The firing strengths are shifted by the nearest
// rule's exponent before exp(), so a sample far from every rule still gets the nearest rules'
// blend instead of 0/0 (a plain evalfis returns NaN there); inside the rules' reach the two agree
// to rounding.
//
// The reader accepts what odonata writes: one output, every rule AND-connected with one
// membership per input, gaussmf inputs, linear or constant outputs; and a rule that leaves an
// input out (0 for that input in the rule line, MATLAB's "don't care"). Anything else is
// refused with a message naming the line.

#include <cmath>
#include <cstddef>
#include <istream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace odonata::inference {

struct TskRule {
  std::vector<double> centre;  ///< c_ji, one per input, raw units
  /// σ_ji > 0; +∞ for an input the rule leaves out (a 0 in a .fis rule line, MATLAB's "don't
  /// care"): its membership is 1 whatever the input.
  std::vector<double> sigma;
  double weight = 1.0;  ///< rule weight in (0, 1]
  /// Linear: a_j1 … a_jN then a_j0 (MATLAB's order, constant last); constant: a_j0 only.
  std::vector<double> coefficients;
  /// The names of the membership functions the rule uses, one per input ("" where it leaves
  /// the input out), and of its output function: the expert's words ("low", "hover").
  std::vector<std::string> terms;
  std::string output_term;
};

struct TskModel {
  std::string name;
  std::vector<std::string> input_names;
  /// Each input's [low, high]; evalfis refuses inputs outside it, Evaluate() does not.
  std::vector<double> input_low, input_high;
  std::string output_name;
  double output_low = 0, output_high = 0;
  bool linear = true;  ///< linear (first order) or constant (zero order) rule outputs
  std::vector<TskRule> rules;

  std::size_t inputs() const { return input_names.size(); }

  /// ŷ for the raw inputs x[0 … n−1]. NaN when n differs from inputs() or there is no rule.
  double Evaluate(const double* x, std::size_t n) const {
    if (n != inputs() || rules.empty()) return std::numeric_limits<double>::quiet_NaN();
    // Two passes: the smallest exponent first, so exp() of the nearest rule is exactly 1.
    double dmin = std::numeric_limits<double>::infinity();
    for (const auto& r : rules) {
      const double d = Distance(r, x);
      if (d < dmin) dmin = d;
    }
    double num = 0, den = 0;
    for (const auto& r : rules) {
      const double w = r.weight * std::exp(-0.5 * (Distance(r, x) - dmin));
      num += w * RuleOutput(r, x);
      den += w;
    }
    return num / den;
  }

  /// Reads a `.fis` file written by odonata (see the header comment for the subset).
  /// @throws std::runtime_error naming the line and what is wrong.
  static TskModel FromFis(std::istream& in) {
    FisSections s = ReadSections(in);
    TskModel m;
    const auto& sys = s.Get("System");
    m.name = Text(sys, "Name");
    if (Text(sys, "Type") != "sugeno") Fail(sys, "Type", "only 'sugeno' systems are supported");
    if (Text(sys, "AndMethod") != "prod") Fail(sys, "AndMethod", "only 'prod' is supported");
    if (Text(sys, "DefuzzMethod") != "wtaver")
      Fail(sys, "DefuzzMethod", "only 'wtaver' is supported");
    const int n = Count(sys, "NumInputs", 1, 100000);
    if (Count(sys, "NumOutputs", 1, 1) != 1) Fail(sys, "NumOutputs", "exactly one output");
    const int nr = Count(sys, "NumRules", 1, 10000000);

    std::vector<std::vector<std::vector<double>>> mfs(static_cast<std::size_t>(n));
    std::vector<std::vector<std::string>> mf_names(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      const auto& in_sec = s.Get("Input" + std::to_string(i + 1));
      m.input_names.push_back(Text(in_sec, "Name"));
      const auto range = Numbers(in_sec, "Range");
      if (range.size() != 2) Fail(in_sec, "Range", "needs [low high]");
      m.input_low.push_back(range[0]);
      m.input_high.push_back(range[1]);
      const int k = Count(in_sec, "NumMFs", 1, 10000000);
      for (int f = 0; f < k; ++f) {
        const auto p = Membership(in_sec, "MF" + std::to_string(f + 1), "gaussmf");
        if (p.size() != 2 || !(p[0] > 0))
          Fail(in_sec, "MF" + std::to_string(f + 1), "gaussmf needs [sigma>0 c]");
        mfs[static_cast<std::size_t>(i)].push_back(p);
        mf_names[static_cast<std::size_t>(i)].push_back(
            MembershipName(in_sec, "MF" + std::to_string(f + 1)));
      }
    }
    const auto& out = s.Get("Output1");
    m.output_name = Text(out, "Name");
    const auto orange = Numbers(out, "Range");
    if (orange.size() != 2) Fail(out, "Range", "needs [low high]");
    m.output_low = orange[0];
    m.output_high = orange[1];
    const int k = Count(out, "NumMFs", 1, 10000000);
    std::vector<std::vector<double>> outs;
    std::vector<std::string> out_names;
    for (int f = 0; f < k; ++f) {
      const std::string key = "MF" + std::to_string(f + 1);
      const std::string type = MembershipType(out, key);
      if (f == 0) m.linear = type == "linear";
      if (type != (m.linear ? "linear" : "constant"))
        Fail(out, key, "every output function must be 'linear', or every one 'constant'");
      auto p = Membership(out, key, type);
      if (p.size() != (m.linear ? static_cast<std::size_t>(n) + 1 : 1u))
        Fail(out, key,
             m.linear ? "a linear output needs NumInputs + 1 coefficients"
                      : "a constant output needs one value");
      outs.push_back(std::move(p));
      out_names.push_back(MembershipName(out, key));
    }

    if (s.rule_lines.size() != static_cast<std::size_t>(nr))
      throw std::runtime_error("fis: [Rules] has " + std::to_string(s.rule_lines.size()) +
                               " rules, NumRules says " + std::to_string(nr));
    for (const auto& [line_no, text] : s.rule_lines) {
      // "a1 a2 … aN, o1 (weight) : connection"
      std::string t = text;
      for (char& c : t)
        if (c == ',' || c == '(' || c == ')' || c == ':') c = ' ';
      std::istringstream ls(t);
      std::vector<double> v;
      double d;
      while (ls >> d) v.push_back(d);
      if (!ls.eof() || v.size() != static_cast<std::size_t>(n) + 3)
        throw std::runtime_error("fis line " + std::to_string(line_no) +
                                 ": a rule needs one membership per input, one output, a weight "
                                 "and a connection");
      TskRule r;
      for (int i = 0; i < n; ++i) {
        if (v[static_cast<std::size_t>(i)] == 0) {
          // "Don't care": the input is not in the rule's premise; as MATLAB's evalfis, its
          // membership is 1 for every value (a Gaussian of infinite width).
          r.sigma.push_back(std::numeric_limits<double>::infinity());
          r.centre.push_back(0.0);
          r.terms.emplace_back();
          continue;
        }
        const auto idx =
            Index(v[static_cast<std::size_t>(i)], mfs[static_cast<std::size_t>(i)].size(), line_no);
        r.sigma.push_back(mfs[static_cast<std::size_t>(i)][idx][0]);
        r.centre.push_back(mfs[static_cast<std::size_t>(i)][idx][1]);
        r.terms.push_back(mf_names[static_cast<std::size_t>(i)][idx]);
      }
      const std::size_t out_index = Index(v[static_cast<std::size_t>(n)], outs.size(), line_no);
      r.coefficients = outs[out_index];
      r.output_term = out_names[out_index];
      r.weight = v[static_cast<std::size_t>(n) + 1];
      if (!(r.weight > 0 && r.weight <= 1))
        throw std::runtime_error("fis line " + std::to_string(line_no) +
                                 ": weight must be in (0, 1]");
      if (v[static_cast<std::size_t>(n) + 2] != 1)
        throw std::runtime_error("fis line " + std::to_string(line_no) + ": only AND (1) rules");
      m.rules.push_back(std::move(r));
    }
    return m;
  }

 private:
  static double Distance(const TskRule& r, const double* x) {
    double d = 0;
    for (std::size_t i = 0; i < r.centre.size(); ++i) {
      if (std::isinf(r.sigma[i])) continue;  // an input the rule leaves out
      const double z = (x[i] - r.centre[i]) / r.sigma[i];
      d += z * z;
    }
    return d;
  }
  double RuleOutput(const TskRule& r, const double* x) const {
    if (!linear) return r.coefficients[0];
    const std::size_t n = inputs();
    double y = r.coefficients[n];
    for (std::size_t i = 0; i < n; ++i) y += r.coefficients[i] * x[i];
    return y;
  }

  struct Section {
    std::string name;
    std::map<std::string, std::pair<int, std::string>> values;  // key → (line, raw value)
  };
  struct FisSections {
    std::map<std::string, Section> sections;
    std::vector<std::pair<int, std::string>> rule_lines;
    const Section& Get(const std::string& name) const {
      const auto it = sections.find(name);
      if (it == sections.end()) throw std::runtime_error("fis: no [" + name + "] section");
      return it->second;
    }
  };

  [[noreturn]] static void Fail(const Section& s, const std::string& key, const std::string& why) {
    const auto it = s.values.find(key);
    const std::string where =
        it == s.values.end() ? "" : " (line " + std::to_string(it->second.first) + ")";
    throw std::runtime_error("fis [" + s.name + "] " + key + where + ": " + why);
  }
  static const std::string& Raw(const Section& s, const std::string& key) {
    const auto it = s.values.find(key);
    if (it == s.values.end()) Fail(s, key, "missing");
    return it->second.second;
  }
  static std::string Unquote(const Section& s, const std::string& key, const std::string& v) {
    if (v.size() < 2 || v.front() != '\'' || v.back() != '\'')
      Fail(s, key, "expected a 'quoted' value");
    return v.substr(1, v.size() - 2);
  }
  static std::string Text(const Section& s, const std::string& key) {
    return Unquote(s, key, Raw(s, key));
  }
  static std::vector<double> ParseNumbers(const Section& s, const std::string& key, std::string v) {
    if (v.size() < 2 || v.front() != '[' || v.back() != ']') Fail(s, key, "expected [numbers]");
    std::istringstream ns(v.substr(1, v.size() - 2));
    std::vector<double> out;
    std::string tok;
    while (ns >> tok) {
      std::size_t used = 0;
      double d = 0;
      try {
        d = std::stod(tok, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != tok.size() || !std::isfinite(d))
        Fail(s, key, "'" + tok + "' is not a finite number");
      out.push_back(d);
    }
    return out;
  }
  static std::vector<double> Numbers(const Section& s, const std::string& key) {
    return ParseNumbers(s, key, Raw(s, key));
  }
  static int Count(const Section& s, const std::string& key, int lo, int hi) {
    const auto v = ParseNumbers(s, key, "[" + Raw(s, key) + "]");
    if (v.size() != 1 || v[0] != std::floor(v[0]) || v[0] < lo || v[0] > hi)
      Fail(s, key,
           "expected a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return static_cast<int>(v[0]);
  }
  // MFk='name':'type',[params]
  static std::string MembershipType(const Section& s, const std::string& key) {
    const std::string& v = Raw(s, key);
    const auto colon = v.find("':'");
    const auto comma = v.find("',[");
    if (colon == std::string::npos || comma == std::string::npos || comma < colon)
      Fail(s, key, "expected 'name':'type',[params]");
    return v.substr(colon + 3, comma - colon - 3);
  }
  // The 'name' of MFk='name':'type',[params].
  static std::string MembershipName(const Section& s, const std::string& key) {
    const std::string& v = Raw(s, key);
    const auto colon = v.find("':'");
    if (v.empty() || v[0] != '\'' || colon == std::string::npos)
      Fail(s, key, "expected 'name':'type',[params]");
    return v.substr(1, colon - 1);
  }
  static std::vector<double> Membership(const Section& s, const std::string& key,
                                        const std::string& type) {
    if (MembershipType(s, key) != type) Fail(s, key, "expected a '" + type + "' function");
    const std::string& v = Raw(s, key);
    return ParseNumbers(s, key, v.substr(v.find("',[") + 2));
  }
  static std::size_t Index(double v, std::size_t count, int line_no) {
    if (v != std::floor(v) || v < 1 || v > static_cast<double>(count))
      throw std::runtime_error(
          "fis line " + std::to_string(line_no) +
          ": membership index out of range (negated terms are not supported; 0 leaves "
          "the input out)");
    return static_cast<std::size_t>(v) - 1;
  }
  static std::string Trim(const std::string& t) {
    const auto b = t.find_first_not_of(" \t\r");
    if (b == std::string::npos) return "";
    return t.substr(b, t.find_last_not_of(" \t\r") - b + 1);
  }
  static FisSections ReadSections(std::istream& in) {
    FisSections out;
    std::string line, current;
    int no = 0;
    while (std::getline(in, line)) {
      ++no;
      const std::string t = Trim(line);
      if (t.empty() || t[0] == '%' || t[0] == '#') continue;
      if (t.front() == '[' && t.back() == ']') {
        current = t.substr(1, t.size() - 2);
        if (out.sections.count(current) || (current == "Rules" && !out.rule_lines.empty()))
          throw std::runtime_error("fis line " + std::to_string(no) + ": [" + current + "] twice");
        if (current != "Rules") out.sections[current].name = current;
        continue;
      }
      if (current.empty())
        throw std::runtime_error("fis line " + std::to_string(no) + ": text before any [section]");
      if (current == "Rules") {
        out.rule_lines.emplace_back(no, t);
        continue;
      }
      const auto eq = t.find('=');
      if (eq == std::string::npos)
        throw std::runtime_error("fis line " + std::to_string(no) + ": expected key=value");
      auto& sec = out.sections[current];
      const std::string key = Trim(t.substr(0, eq));
      if (!sec.values.emplace(key, std::make_pair(no, Trim(t.substr(eq + 1)))).second)
        throw std::runtime_error("fis line " + std::to_string(no) + ": " + key + " twice in [" +
                                 current + "]");
    }
    return out;
  }
};

}  // namespace odonata::inference
