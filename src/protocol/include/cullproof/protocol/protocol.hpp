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
#include <vector>

namespace cullproof::protocol {

/// A method a program offers, as its handshake describes it.
struct OfferedMethod {
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

/// A line as messages quote it: its first 200 bytes, then "..." if there is more.
std::string excerpt(std::string_view line);

}  // namespace cullproof::protocol
