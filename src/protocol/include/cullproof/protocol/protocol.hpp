// The process protocol's messages from a program (docs/protocol.md), read from one line of text:
// the handshake and the answer to a frame. external.cpp runs the program and hands each line it
// reads (already within the line limits of cullproof/protocol/external.hpp) to these readers, which hold no
// state and can be tested on any text.
#pragma once

#include "cullproof/methods/methods.hpp"
#include "cullproof/systems/system.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace cullproof::protocol {

/// A method a program offers, as its handshake describes it.
struct OfferedMethod {
  /// Its place in the handshake's "methods" (a binary frame names its method by this index).
  std::uint32_t index = 0;
  /// The handshake's "encoding" (version 3): method frames and their answers in binary.
  bool binary = false;
  /// name, description, source, claim, tolerance, volumes, three_way, stateful, touching and origin
  /// (user unless "published"); `program` is left empty.
  MethodInfo info;
  bool wants_matrix = false;  ///< "frustum": "matrix": asked only about frusta given by a clip matrix
  /// "depth" (with "frustum": "matrix"): the depth conventions it reads, a bit per
  /// depth_convention_bit; the others' cases count as not applying. All four when not declared.
  unsigned depths = 0xF;
};

/// The bit of a depth convention in OfferedMethod::depths: negative_one_to_one 1, zero_to_one 2,
/// reversed: the same shifted left by 2.
unsigned depth_convention_bit(const DepthConvention& d) noexcept;

/// Reads the handshake line of the program whose command line is `program`. Throws
/// std::runtime_error "external program '<program>': ..." naming what is wrong: a line that is not
/// JSON or nests past kMaxProtocolDepth, another protocol version, no methods, a method without a
/// name or named twice, a field of the wrong type or outside its list of values.
std::vector<OfferedMethod> parse_handshake(std::string_view line, const std::string& program);

/// A culler described in a file of its own (a shader's description, docs/gpu.md): one JSON object
/// with a method's fields as a handshake entry has them (name, description, source, claim,
/// tolerance, volumes, three_way, touching, origin; not stateful, frustum, depth) and the string
/// fields `extra` names; `strings` holds those present. Throws std::runtime_error
/// "<where>: ..." naming what is wrong, as parse_handshake does (an unknown field included).
struct MethodDescription {
  MethodInfo info;
  std::vector<std::pair<std::string, std::string>> strings;
};
MethodDescription parse_method_description(std::string_view text, const std::string& where,
                                           const std::vector<std::string>& extra);

/// The culling systems a version-2 handshake offers ("systems": name, description, source,
/// claim, tolerance, volumes, three_way, touching, origin; no other field); none for version 1.
/// Throws std::runtime_error as parse_handshake does, naming the field (an unknown one included).
std::vector<SystemInfo> parse_offered_systems(std::string_view line, const std::string& program);

/// Reads the answer to a scene or update message, {"frame": n, "<key>": true}; `what` names the
/// message. Throws std::runtime_error "answered <what> ..." as parse_answer does.
void parse_acknowledgement(std::string_view line, std::uint64_t frame, const char* key, const std::string& what);

/// A program's answer to a cull message: the visible set and its own time.
struct VisibleReply {
  VisibleSet set;
  std::optional<double> ns;
};
/// Reads the answer to cull message `frame` for a system given `objects` objects:
/// {"frame": n, "visible": [ids], "verdicts": ["inside" | "intersecting", ...], "ns": x}, the
/// verdicts one per id (required of a three-way system, optional of a two-way one, which may
/// not answer "inside"). Throws std::runtime_error "answered <what> ..." for more ids than
/// objects, an id that is not an integer from 0 to 2^32 - 1, verdicts of another count or value,
/// and what parse_answer refuses. Whether the ids are the scene's, once each, the judge checks.
VisibleReply parse_visible(std::string_view line, std::uint64_t frame, std::size_t objects, bool three_way,
                           const std::string& what);

/// A program's answer to one frame.
struct Reply {
  std::vector<Answer> verdicts;  ///< one per volume, in order; std::nullopt: does not apply
  std::optional<double> ns;      ///< the program's own time for the frame, when it gives one
};

/// Reads the answer line to frame number `frame` of `volumes` volumes; `what` names the frame in
/// messages ("frame 3 (1 volume(s) for method 'x')"). Throws std::runtime_error "answered <what>
/// ..." for a line that is not JSON or nests past kMaxProtocolDepth, another frame number, an
/// "error" the program reports, a missing "verdicts" array or one of another length, a verdict
/// that is not "outside", "intersecting", "inside" or null, or an "ns" that is not a number >= 0.
Reply parse_answer(std::string_view line, std::uint64_t frame, std::size_t volumes, const std::string& what);

// ---- The binary encoding of method frames and answers (version 3, "encoding": "binary")

/// The first four bytes of a binary frame message ("CP3F") and of its answer ("CP3A").
constexpr char kBinaryFramesMagic[4] = {'C', 'P', '3', 'F'};
constexpr char kBinaryAnswerMagic[4] = {'C', 'P', '3', 'A'};
/// A binary verdict byte: Visibility's value (0 outside, 1 intersecting, 2 inside), or this for a
/// method that does not apply to the volume.
constexpr std::uint8_t kBinaryNotApplying = 255;
/// Bytes of a binary answer's header (magic, frame count) and of each frame's (frame number,
/// verdict count, ns), before its verdict bytes.
constexpr std::size_t kBinaryAnswerHeader = 8;
constexpr std::size_t kBinaryAnswerFrameHeader = 20;

/// One frame of a binary message, as asked: its number and how many volumes it holds.
struct AskedFrame {
  std::uint64_t frame = 0;
  std::size_t volumes = 0;
};
/// The size in bytes of the binary answer to `frames` (the program's answer has exactly this
/// size; cullproof reads no more).
std::size_t binary_answer_size(const std::vector<AskedFrame>& frames) noexcept;
/// Appends to `out` the binary frame entry of method `method` (its handshake index) for frame
/// number `frame`: `reset` as the JSON frame's, the planes, the matrix and its depth convention
/// when the frustum has one, then the volumes (all of one kind; throws std::invalid_argument
/// otherwise). `binary_message` puts entries into a message.
void append_binary_frame(std::string& out, std::uint64_t frame, std::uint32_t method, bool reset, const CaseFrustum& f,
                         const Volume* volumes, std::size_t n);
/// Bytes of a binary frame message's header: the magic, the frame count, the bytes that follow.
constexpr std::size_t kBinaryFramesHeader = 12;
/// Makes `message`, kBinaryFramesHeader bytes followed by `frames` entries (append_binary_frame),
/// a binary frame message: writes its header over the first bytes.
void put_binary_header(std::string& message, std::size_t frames);
/// Checks the first kBinaryAnswerHeader bytes of a binary answer: its magic and frame count (so
/// that an answer of the wrong shape is refused before the rest is awaited). Throws as
/// parse_binary_answer does.
void check_binary_answer_header(std::string_view bytes, const std::vector<AskedFrame>& frames, const std::string& what);
/// Reads a binary answer (binary_answer_size(frames) bytes) to the frames asked; `what` names the
/// message. Throws std::runtime_error "answered <what> ..." (or "answered frame F of <what> ...")
/// for another size, magic, frame count, frame number or verdict count, a verdict byte that is not
/// 0, 1, 2 or 255, or an ns that is neither a number >= 0 nor -1 (not given).
std::vector<Reply> parse_binary_answer(std::string_view bytes, const std::vector<AskedFrame>& frames, const std::string& what);
/// Reads the JSON line a program writes instead of a binary answer: {"frame": F, "error": "..."}
/// with F the message's first frame. Always throws: the error it reports, or what is wrong with
/// the line.
[[noreturn]] void refuse_json_instead_of_binary(std::string_view line, std::uint64_t first_frame, const std::string& what);

/// A line as messages quote it: its first 200 bytes, then "..." if there is more.
std::string excerpt(std::string_view line);

}  // namespace cullproof::protocol
