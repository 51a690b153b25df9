#pragma once
/// \file parsing.h
/// Building blocks shared by the format readers and writers of mesh_io.h: the whole file in
/// memory, a line cursor for text formats and a byte cursor for binary ones (both throw
/// InputError with file name and line / byte offset), number parsing with std::from_chars, and
/// an output buffer with exact shortest-round-trip number printing. Used by cpp/src/io only;
/// exported because it is small and useful to C++ users writing their own readers.
#include <meshsmith/core/errors.h>
#include <meshsmith/io/mesh_io.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

namespace meshsmith::io {

/// The whole content of a file, read-only: a private memory map of the file (POSIX) or, where
/// mapping is not possible, a buffer it was read into.
class FileContents {
 public:
  FileContents(std::unique_ptr<char[]> data, std::size_t size) : buffer_(std::move(data)), size_(size) {}
  FileContents(const void* mapping, std::size_t size) : mapping_(mapping), size_(size) {}
  FileContents(FileContents&& other) noexcept
      : buffer_(std::move(other.buffer_)), mapping_(other.mapping_), size_(other.size_) {
    other.mapping_ = nullptr;
  }
  FileContents(const FileContents&) = delete;
  FileContents& operator=(const FileContents&) = delete;
  FileContents& operator=(FileContents&&) = delete;
  ~FileContents();

  std::string_view bytes() const {
    return {mapping_ ? static_cast<const char*>(mapping_) : buffer_.get(), size_};
  }
  operator std::string_view() const { return bytes(); }

 private:
  std::unique_ptr<char[]> buffer_;
  const void* mapping_ = nullptr;
  std::size_t size_;
};

/// The whole content of `path`.
/// \throw InputError if the file does not exist, is a directory or not a regular file, cannot be
///        read, or is empty.
FileContents read_file_contents(const std::string& path);

/// Writes `contents` to `path` (replacing it).
/// \throw InputError if the file cannot be opened or written.
void write_file_contents(const std::string& path, std::string_view contents);

/// True for ' ', '\t', '\r', '\v', '\f' (not '\n', which ends a line).
inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/// `text` with every byte outside printable ASCII written as \xNN, so that an error message
/// stays valid UTF-8 whatever bytes the file holds.
inline std::string printable(std::string_view text) {
  static const char hex[] = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c >= 32 && c < 127) {
      out.push_back(ch);
    } else {
      out += "\\x";
      out.push_back(hex[c >> 4]);
      out.push_back(hex[c & 15]);
    }
  }
  return out;
}

/// `token` in single quotes for an error message, cut at 40 characters.
inline std::string quoted(std::string_view token) {
  return "'" + std::string(token.substr(0, 40)) + (token.size() > 40 ? "...'" : "'");
}

/// Clinger's fast path: a decimal with at most 19 digits whose digits form an integer m <= 2^53
/// and whose power of ten e is within [-22, 22] is m * 10^e or m / 10^-e, both exactly
/// representable, so one correctly rounded IEEE operation gives the correctly rounded value.
/// False (nothing parsed) for anything else; the caller then uses std::from_chars.
inline bool parse_simple_decimal(const char* first, const char* last, double& value) {
  static constexpr double powers[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                      1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                      1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  const bool negative = first != last && *first == '-';
  if (negative) ++first;
  std::uint64_t mantissa = 0;
  int digits = 0, exponent = 0;
  const char* p = first;
  for (; p != last && static_cast<unsigned>(*p - '0') <= 9; ++p, ++digits)
    mantissa = mantissa * 10 + static_cast<unsigned>(*p - '0');
  const int integer_digits = digits;
  if (p != last && *p == '.') {
    for (++p; p != last && static_cast<unsigned>(*p - '0') <= 9; ++p, ++digits, --exponent)
      mantissa = mantissa * 10 + static_cast<unsigned>(*p - '0');
    if (digits == integer_digits && integer_digits == 0) return false;  // "." alone
  }
  if (digits == 0 || digits > 19) return false;
  if (p != last && (*p == 'e' || *p == 'E')) {
    ++p;
    const bool negative_exponent = p != last && *p == '-';
    if (p != last && (*p == '-' || *p == '+')) ++p;
    if (p == last) return false;
    int written = 0;
    for (; p != last && static_cast<unsigned>(*p - '0') <= 9; ++p) {
      written = written * 10 + (*p - '0');
      if (written > 1000) return false;
    }
    exponent += negative_exponent ? -written : written;
  }
  if (p != last || mantissa > (std::uint64_t(1) << 53) || exponent < -22 || exponent > 22)
    return false;
  const double m = static_cast<double>(mantissa);
  const double result = exponent < 0 ? m / powers[-exponent] : m * powers[exponent];
  value = negative ? -result : result;
  return true;
}

/// Parses all of `token` as a finite double (a leading '+' is accepted). False otherwise.
/// Exact: the correctly rounded double of the decimal, as std::from_chars gives.
inline bool parse_double(std::string_view token, double& value) {
  if (parse_simple_decimal(token.data(), token.data() + token.size(), value)) return true;
  const char* first = token.data();
  const char* last = first + token.size();
  if (first != last && *first == '+') ++first;
  if (first == last) return false;
  auto [end, error] = std::from_chars(first, last, value);
  if (error != std::errc() || end != last) return false;
  return value - value == 0.0;  // rejects inf and nan
}

/// Parses all of `token` as a decimal integer (an optional sign, '+' included). False otherwise,
/// and for values outside int64.
inline bool parse_integer(std::string_view token, std::int64_t& value) {
  const char* first = token.data();
  const char* last = first + token.size();
  const bool negative = first != last && *first == '-';
  if (first != last && (*first == '+' || *first == '-')) ++first;
  if (first == last) return false;
  if (last - first > 18) {  // might overflow: let from_chars decide
    if (*first == '-' || *first == '+') return false;  // a second sign
    if (negative) --first;
    auto [end, error] = std::from_chars(first, last, value);
    return error == std::errc() && end == last;
  }
  std::int64_t result = 0;
  for (; first != last; ++first) {
    const unsigned digit = static_cast<unsigned>(*first) - '0';
    if (digit > 9) return false;
    result = result * 10 + digit;
  }
  value = negative ? -result : result;
  return true;
}

/// Splits a line into whitespace-separated tokens.
class Tokens {
 public:
  explicit Tokens(std::string_view line) : rest_(line) {}
  /// The next token, or false at the end of the line.
  bool next(std::string_view& token) {
    std::size_t i = 0;
    while (i < rest_.size() && is_blank(rest_[i])) ++i;
    if (i == rest_.size()) { rest_ = {}; return false; }
    std::size_t j = i;
    while (j < rest_.size() && !is_blank(rest_[j])) ++j;
    token = rest_.substr(i, j - i);
    rest_ = rest_.substr(j);
    return true;
  }
  /// True when only blanks remain.
  bool empty() const {
    for (char c : rest_) if (!is_blank(c)) return false;
    return true;
  }
  std::string_view rest() const { return rest_; }

 private:
  std::string_view rest_;
};

/// Walks a text buffer line by line ('\n' or "\r\n" endings) and reports errors with the line.
class LineReader {
 public:
  LineReader(const std::string& path, std::string_view text, std::size_t first_line = 1)
      : path_(path), text_(text), line_number_(first_line - 1) {}

  /// The next line (without its ending), or false at the end of the text.
  bool next(std::string_view& line) {
    if (position_ >= text_.size()) return false;
    const char* begin = text_.data() + position_;
    const void* newline = std::memchr(begin, '\n', text_.size() - position_);
    std::size_t length = newline ? static_cast<const char*>(newline) - begin : text_.size() - position_;
    position_ += length + (newline ? 1 : 0);
    if (length > 0 && begin[length - 1] == '\r') --length;
    line = std::string_view(begin, length);
    ++line_number_;
    return true;
  }

  /// The next line that is not blank and, when `comment` is not 0, does not start with it
  /// (after blanks). False at the end of the text.
  bool next_content(std::string_view& line, char comment = '#') {
    while (next(line)) {
      std::size_t i = 0;
      while (i < line.size() && is_blank(line[i])) ++i;
      if (i < line.size() && line[i] != comment) return true;
    }
    return false;
  }

  std::size_t line_number() const { return line_number_; }
  std::size_t offset() const { return position_; }
  std::size_t remaining_bytes() const { return text_.size() - position_; }
  const std::string& path() const { return path_; }

  /// Throws InputError "<path>: line <n>: <message>".
  [[noreturn]] void fail(const std::string& message) const {
    throw InputError(path_ + ": line " + std::to_string(line_number_) + ": " + printable(message));
  }

 private:
  const std::string& path_;
  std::string_view text_;
  std::size_t position_ = 0;
  std::size_t line_number_ = 0;
};

/// Reads fixed-size little- or big-endian values from a byte buffer, checking every read.
class ByteReader {
 public:
  ByteReader(const std::string& path, std::string_view bytes, std::size_t offset, bool big_endian)
      : path_(path), bytes_(bytes), position_(offset), swap_(big_endian != host_is_big_endian()) {}

  static bool host_is_big_endian() {
    const std::uint16_t probe = 1;
    unsigned char first;
    std::memcpy(&first, &probe, 1);
    return first == 0;
  }

  /// Reads a T (arithmetic) at the current offset and advances.
  /// \throw InputError "unexpected end of file" naming `what` and the offset.
  template <typename T>
  T read(const char* what) {
    require(sizeof(T), what);
    T value = decode<T>(bytes_.data() + position_, swap_);
    position_ += sizeof(T);
    return value;
  }

  /// Decodes a T stored at `data` (swap bytes when `swap`).
  template <typename T>
  static T decode(const char* data, bool swap) {
    static_assert(std::is_arithmetic_v<T>);
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, data, sizeof(T));
    if (swap)
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
    T value;
    std::memcpy(&value, raw, sizeof(T));
    return value;
  }

  /// \throw InputError unless `count` more bytes are available.
  void require(std::size_t count, const char* what) const {
    if (count > bytes_.size() - position_)
      fail("unexpected end of file while reading " + std::string(what) + " (" +
           std::to_string(count) + " bytes needed, " + std::to_string(bytes_.size() - position_) +
           " left)");
  }

  void skip(std::size_t count, const char* what) { require(count, what); position_ += count; }
  const char* here() const { return bytes_.data() + position_; }
  std::size_t offset() const { return position_; }
  std::size_t remaining_bytes() const { return bytes_.size() - position_; }
  bool swap() const { return swap_; }
  const std::string& path() const { return path_; }

  /// Throws InputError "<path>: byte <offset>: <message>".
  [[noreturn]] void fail(const std::string& message) const { fail_at(position_, message); }
  [[noreturn]] void fail_at(std::size_t offset, const std::string& message) const {
    throw InputError(path_ + ": byte " + std::to_string(offset) + ": " + printable(message));
  }

 private:
  const std::string& path_;
  std::string_view bytes_;
  std::size_t position_;
  bool swap_;
};

/// An output buffer for writers: text with exact numbers, and raw binary values. Appends are
/// inlined copies into a buffer grown geometrically.
class OutputBuffer {
 public:
  void text(std::string_view s) { std::memcpy(room(s.size()), s.data(), s.size()); used_ += s.size(); }
  void character(char c) { *room(1) = c; ++used_; }
  /// Shortest decimal form that reads back to exactly `value` (std::to_chars).
  void number(double value) {
    char* at = room(32);
    used_ = std::to_chars(at, at + 32, value).ptr - data_.data();
  }
  void number(std::int64_t value) {
    char* at = room(24);
    used_ = std::to_chars(at, at + 24, value).ptr - data_.data();
  }
  void number(int value) { number(static_cast<std::int64_t>(value)); }
  /// Appends the bytes of `value`, byte-swapped when `big_endian` differs from the host.
  template <typename T>
  void binary(T value, bool big_endian) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    if (big_endian != ByteReader::host_is_big_endian())
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
    std::memcpy(room(sizeof(T)), raw, sizeof(T));
    used_ += sizeof(T);
  }
  /// Appends `bytes` bytes for the caller to fill through the returned pointer (valid until the
  /// next append).
  char* extend(std::size_t bytes) {
    char* at = room(bytes);
    used_ += bytes;
    return at;
  }
  /// Makes room for `bytes` more bytes in one allocation.
  void reserve(std::size_t bytes) { room(bytes); }
  std::string_view contents() const { return {data_.data(), used_}; }
  /// Moves the buffer out (the OutputBuffer is empty afterwards).
  std::string take() {
    data_.resize(used_);
    used_ = 0;
    return std::move(data_);
  }

 private:
  /// Pointer to the end of the contents, with at least `bytes` writable bytes after it.
  char* room(std::size_t bytes) {
    if (data_.size() - used_ < bytes) data_.resize(std::max(2 * data_.size(), used_ + bytes));
    return data_.data() + used_;
  }

  std::string data_;
  std::size_t used_ = 0;
};

/// Appends one text line "count i j k ..." per face of `mesh`, followed by the face's row of
/// `face_values` when given: the face records of ASCII OFF (with colours) and of ASCII PLY's
/// vertex_indices lists.
inline void append_face_lines(OutputBuffer& out, const PolygonMesh& mesh,
                              const ColorMatrix* face_values = nullptr) {
  for (std::int64_t f = 0; f < mesh.face_count(); ++f) {
    const std::int64_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    out.number(end - begin);
    for (std::int64_t k = begin; k < end; ++k) {
      out.character(' ');
      out.number(mesh.face_vertices[k]);
    }
    if (face_values)
      for (Eigen::Index c = 0; c < face_values->cols(); ++c) {
        out.character(' ');
        out.number((*face_values)(f, c));
      }
    out.character('\n');
  }
}

}  // namespace meshsmith::io
