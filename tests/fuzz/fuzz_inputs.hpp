// What the readers of untrusted input promise, checked on any bytes. Each function runs one reader
// on `bytes` and returns when the reader either read them or refused them with its documented
// error, whose message names the source; for what it read it also checks that writing it out and
// reading that again gives the same text. Anything else escapes: another exception (a JSON
// library's type error, std::out_of_range, std::bad_alloc) or a FuzzFailure naming the broken
// promise. The libFuzzer targets (fuzz_main.cpp) call them on generated inputs; test_fuzz_inputs
// replays the committed seeds and the inputs that once broke a reader.
#pragma once

#include <stdexcept>
#include <string_view>

namespace cullproof::fuzz {

/// A reader broke a promise that is not about an error of the input.
class FuzzFailure : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

/// The case reader: the bytes as one case (parse_case) and as JSON Lines (parse_cases_jsonl).
void case_reader(std::string_view bytes);
/// The scene reader (sim::parse_scene_text).
void scene_reader(std::string_view bytes);
/// The corpus reader: the bytes as a corpus file (parse_corpus_entry), with its camera path.
void corpus_reader(std::string_view bytes);
/// The process protocol's readers: the bytes as a program's handshake, its answer to a frame (a
/// JSON line) and its binary answer to one frame or two.
void protocol_reader(std::string_view bytes);

}  // namespace cullproof::fuzz
