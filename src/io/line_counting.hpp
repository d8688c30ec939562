// The line counting shared by the readers of src/io: an iterator over JSON text that keeps the
// line of the last character the parser consumed, so that an error names its line.
#pragma once

#include <cctype>
#include <cstddef>
#include <iterator>

namespace cullproof::io_detail {

struct LineState {
  int line = 1;
  int token_line = 1;  // line of the last non-blank character consumed
  const char* begin = nullptr;  // the text
  const char* next = nullptr;   // the next character the parser will read
};

struct CountingIterator {
  using iterator_category = std::forward_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;
  const char* p = nullptr;
  LineState* st = nullptr;
  reference operator*() const { return *p; }
  CountingIterator& operator++() {
    if (*p == '\n') ++st->line;
    else if (!std::isspace(static_cast<unsigned char>(*p))) st->token_line = st->line;
    ++p;
    st->next = p;
    return *this;
  }
  CountingIterator operator++(int) { CountingIterator t = *this; ++*this; return t; }
  bool operator==(const CountingIterator& o) const { return p == o.p; }
  bool operator!=(const CountingIterator& o) const { return p != o.p; }
};

}  // namespace cullproof::io_detail
