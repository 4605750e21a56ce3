// Physical lines of a CL file, read through a fixed buffer so that a line is never longer in
// memory than the limit the caller sets (a 2 GB file without a newline must not be slurped).
//
// Internal to the CL reader (cl/record.cpp reads through it); not installed.
#pragma once

#include <cstddef>
#include <cstring>
#include <istream>
#include <memory>
#include <string>

#include "redpost/io/error.hpp"

namespace redpost::detail {

class ClLineSource {
 public:
  ClLineSource(std::istream& in, const std::string& source_name, std::size_t max_line_bytes)
      : in_(in),
        source_(source_name),
        max_line_bytes_(max_line_bytes),
        buffer_(std::make_unique<char[]>(kBufferBytes)) {}

  // The next physical line without its "\n" or "\r\n", into `line` (reused). False at the end.
  // Throws Error(bad_input) for a line longer than max_line_bytes, Error(io) for a read failure.
  bool next(std::string& line) {
    line.clear();
    bool got_any = false;
    for (;;) {
      if (begin_ == end_ && !refill())
        break;
      got_any = true;
      const char* start = buffer_.get() + begin_;
      const std::size_t available = end_ - begin_;
      const void* nl = std::memchr(start, '\n', available);
      const std::size_t take =
          nl ? static_cast<std::size_t>(static_cast<const char*>(nl) - start) : available;
      if (line.size() + take > max_line_bytes_ + 1)  // +1: a "\r" that will be dropped
        too_long(line);
      line.append(start, take);
      begin_ += take;
      if (nl) {
        ++begin_;  // the newline
        break;
      }
    }
    if (!got_any)
      return false;
    if (!line.empty() && line.back() == '\r')
      line.pop_back();
    if (line.size() > max_line_bytes_)
      too_long(line);
    // A UTF-8 byte order mark (Windows editors write one) is not part of the first record.
    if (line_number_ == 0 && line.compare(0, 3, "\xEF\xBB\xBF") == 0)
      line.erase(0, 3);
    if (const std::size_t cr = line.find('\r'); cr != std::string::npos && !binary(line, cr))
      stray_cr(static_cast<int>(cr) + 1);
    ++line_number_;
    return true;
  }

  // 1-based number of the line last returned by next().
  int line_number() const { return line_number_; }

 private:
  static constexpr std::size_t kBufferBytes = 64 * 1024;

  bool refill() {
    begin_ = end_ = 0;
    std::streambuf* sb = in_.rdbuf();
    if (!sb || in_.bad())
      throw Error(ErrorCode::io, "cannot read the CL stream", SourceLocation{source_, 0, 0});
    std::streamsize got = 0;
    try {
      got = sb->sgetn(buffer_.get(), kBufferBytes);
    } catch (const std::ios_base::failure&) {  // libstdc++'s filebuf on a failed read()
      throw Error(ErrorCode::io, "read error: is it a readable regular file?",
                  SourceLocation{source_, line_number_ + 1, 0});
    }
    if (got <= 0) {
      in_.setstate(std::ios::eofbit);
      return false;
    }
    end_ = static_cast<std::size_t>(got);
    return true;
  }

  // A CR inside a line: the file's lines end in CR alone (classic Mac OS), which would make the
  // whole file one record, or a stray CR sits in a record.
  [[noreturn]] void stray_cr(int column) const {
    throw Error(ErrorCode::bad_input,
                "a carriage return (CR, 0x0D) inside the line: the file's lines end in CR alone "
                "(classic Mac OS line endings), or a record holds a stray CR; convert the line "
                "endings to LF or CR LF (for example: tr '\\r' '\\n' < in.apt > out.apt)",
                SourceLocation{source_, line_number_ + 1, column});
  }

  // Control bytes before `end` (a tab aside): binary data, a compressed file given by mistake,
  // whose CR bytes are no line endings; the record parser names the first byte.
  static bool binary(const std::string& line, std::size_t end) {
    for (std::size_t i = 0; i < end; ++i) {
      const auto u = static_cast<unsigned char>(line[i]);
      if ((u < 0x20 && u != '\t') || u == 0x7f)
        return true;
    }
    return false;
  }

  [[noreturn]] void too_long(const std::string& line_so_far) const {
    if (const std::size_t cr = line_so_far.find('\r');
        cr != std::string::npos && !binary(line_so_far, cr))
      stray_cr(static_cast<int>(cr) + 1);
    throw Error(ErrorCode::bad_input,
                "line longer than " + std::to_string(max_line_bytes_) +
                    " bytes (is this a CL text file? raise ClReaderOptions::max_line_bytes "
                    "if it is)",
                SourceLocation{source_, line_number_ + 1, 0});
  }

  std::istream& in_;
  std::string source_;
  std::size_t max_line_bytes_;
  std::unique_ptr<char[]> buffer_;
  std::size_t begin_ = 0;
  std::size_t end_ = 0;
  int line_number_ = 0;
};

}  // namespace redpost::detail
