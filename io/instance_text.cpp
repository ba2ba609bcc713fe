#include "io/instance_text.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>

#include "io/memory_budget.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/printable_text.hpp"

namespace trackassoc {
namespace {

// Walks whitespace-separated tokens of a text, counting lines for error messages. Tokens are
// views into the text: a 125 000-number instance is parsed without copying it token by token.
class Tokenizer {
 public:
  Tokenizer(std::string_view text, const std::string& source) : text_(text), source_(source) {}

  // The next token, or an empty view at the end of the text.
  std::string_view next() {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    token_line_ = line_;
    return text_.substr(start, pos_ - start);
  }
  int line() const { return token_line_; }
  // How many tokens are left, without consuming them.
  std::size_t count_remaining() const {
    std::size_t n = 0;
    for (std::size_t i = pos_; i < text_.size(); ++i)
      if (!is_space(text_[i]) && (i == pos_ || is_space(text_[i - 1]))) ++n;
    return n;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(source_ + ": line " + std::to_string(token_line_) + ": " + what);
  }

 private:
  static bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
  }
  std::string_view text_;
  const std::string& source_;
  std::size_t pos_ = 0;
  int line_ = 1, token_line_ = 1;
};

// Garbage can be long or binary: a short escaped prefix (kernels/core/printable_text.hpp).
std::string shown(std::string_view token) { return quoted_preview(token, 24); }

// A strictly positive integer size in [1, 2^31).
int32_t parse_size(Tokenizer& tok, const std::string& what) {
  const std::string_view t = tok.next();
  if (t.empty()) tok.fail("expected " + what + ", found the end of the text");
  int64_t value = 0;
  for (char c : t) {
    if (c < '0' || c > '9') {
      if (t[0] == '-') tok.fail(what + " must be a positive integer, found " + shown(t));
      tok.fail("expected " + what + " (a positive integer), found " + shown(t));
    }
    value = value * 10 + (c - '0');
    if (value > std::numeric_limits<int32_t>::max()) tok.fail(what + " is too large: " + shown(t));
  }
  if (value == 0) tok.fail(what + " must be positive, found 0");
  return static_cast<int32_t>(value);
}

// A finite number that fits a float. strtod needs a NUL-terminated string: the token is copied
// into a small buffer (costs are short).
float parse_cost(Tokenizer& tok, std::string_view t, std::size_t index) {
  char buffer[64];
  if (t.size() >= sizeof(buffer))
    tok.fail("cost #" + std::to_string(index) + " is not a number: " + shown(t));
  t.copy(buffer, t.size());
  buffer[t.size()] = '\0';
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(buffer, &end);
  if (end != buffer + t.size() || t.empty())
    tok.fail("cost #" + std::to_string(index) + " is not a number: " + shown(t));
  if (!std::isfinite(v) || std::fabs(v) > std::numeric_limits<float>::max())
    tok.fail("cost #" + std::to_string(index) + " must be finite (and fit a float), found " + shown(t));
  return static_cast<float>(v);
}

std::string read_whole_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path + ": read error");
  return ss.str();
}

}  // namespace

CostTensor3 parse_3dap_instance(const std::string& text, const std::string& source,
                                std::size_t max_elements) {
  Tokenizer tok(text, source);
  const std::string_view first = tok.next();
  if (first.empty())
    throw InputError(source + ": empty instance (expected the number of dimensions on line 1)");
  if (first != "3") {
    bool digits = !first.empty();
    for (char c : first) digits = digits && c >= '0' && c <= '9';
    if (digits)
      tok.fail("number of dimensions is " + std::string(first) +
               "; only 3-D assignment instances are supported by this reader");
    tok.fail("expected the number of dimensions (3), found " + shown(first));
  }
  const int32_t n1 = parse_size(tok, "n1"), n2 = parse_size(tok, "n2"), n3 = parse_size(tok, "n3");
  // The product of three int32 sizes can overflow 64 bits: compare it in long double first.
  const long double exact = static_cast<long double>(n1) * n2 * n3;
  if (exact > static_cast<long double>(max_elements))
    throw InputError(source + ": tensor " + std::to_string(n1) + "x" + std::to_string(n2) + "x" +
                     std::to_string(n3) + " has more than the allowed " + std::to_string(max_elements) +
                     " elements");
  const std::size_t count = static_cast<std::size_t>(n1) * n2 * n3;
  // Both checks come before the tensor is allocated: a short header must not cost gigabytes. A
  // text with too few numbers still reports garbage among them first (with its line).
  const std::string size = std::to_string(n1) + "x" + std::to_string(n2) + "x" + std::to_string(n3);
  if (const std::size_t left = tok.count_remaining(); left < count) {
    for (std::size_t i = 0; i < left; ++i) parse_cost(tok, tok.next(), i + 1);
    tok.fail("too few costs: expected " + std::to_string(count) + " (" + size + "), found " +
             std::to_string(left));
  }
  CostTensor3 b;
  require_memory(count * sizeof(b.cost[0]), source + ": tensor " + size);
  b.n1 = n1;
  b.n2 = n2;
  b.n3 = n3;
  b.cost.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::string_view t = tok.next();
    if (t.empty())
      tok.fail("too few costs: expected " + std::to_string(count) + " (" + std::to_string(n1) + "x" +
               std::to_string(n2) + "x" + std::to_string(n3) + "), found " + std::to_string(i));
    b.cost[i] = parse_cost(tok, t, i + 1);
  }
  const std::string_view extra = tok.next();
  if (!extra.empty())
    tok.fail("too many numbers: expected " + std::to_string(count) + " costs, found more, starting with " +
             shown(extra));
  return b;
}

CostTensor3 read_3dap_instance(const std::string& path) {
  return parse_3dap_instance(read_whole_file(path), path);
}

std::map<std::string, double> read_known_optima(const std::string& path) {
  const std::string text = read_whole_file(path);
  std::map<std::string, double> optima;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    std::istringstream fields(line);
    std::string name, value, extra;
    if (!(fields >> name)) continue;  // blank line
    const std::string where = path + ": line " + std::to_string(number);
    if (!(fields >> value)) throw InputError(where + ": expected 'name value', found only " + shown(name));
    if (fields >> extra) throw InputError(where + ": expected 'name value', found extra " + shown(extra));
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (end != value.c_str() + value.size() || !std::isfinite(v))
      throw InputError(where + ": optimum of " + shown(name) + " is not a finite number: " + shown(value));
    if (!optima.emplace(name, v).second) throw InputError(where + ": " + shown(name) + " is listed twice");
  }
  if (optima.empty()) throw InputError(path + ": no 'name value' lines");
  return optima;
}

Solution3File read_3dap_solution(const std::string& path) {
  const std::string text = read_whole_file(path);
  std::istringstream in(text);
  std::string line;
  Solution3File sol;
  bool have_optimum = false;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::string where = path + ": line " + std::to_string(number);
    std::istringstream fields(line);
    std::string first;
    if (!(fields >> first)) continue;
    if (first == "OPT:") {
      if (have_optimum) throw InputError(where + ": second 'OPT:' line");
      std::string value;
      if (!(fields >> value)) throw InputError(where + ": 'OPT:' without a value");
      char* end = nullptr;
      sol.optimum = std::strtod(value.c_str(), &end);
      if (end != value.c_str() + value.size() || !std::isfinite(sol.optimum))
        throw InputError(where + ": optimum is not a finite number: " + shown(value));
      have_optimum = true;
      continue;
    }
    Tuple3 t{};
    std::istringstream all(line);
    std::string extra;
    for (int d = 0; d < 3; ++d) {
      long v = 0;
      if (!(all >> v) || v < 1 || v > std::numeric_limits<int32_t>::max())
        throw InputError(where + ": expected three 1-based indices 'i j k'");
      t[d] = static_cast<int32_t>(v - 1);
    }
    if (all >> extra) throw InputError(where + ": expected three indices, found extra " + shown(extra));
    sol.tuples.push_back(t);
  }
  if (!have_optimum) throw InputError(path + ": no 'OPT: value' line");
  return sol;
}

}  // namespace trackassoc
