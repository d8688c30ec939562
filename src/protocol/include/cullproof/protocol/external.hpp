// Cullers in any language: a program that speaks the cullproof process protocol (JSON Lines over
// its stdin and stdout, or binary method frames, docs/protocol.md) becomes a Method like any
// other, verified, shrunk and recorded the same way. The program is started once; its methods
// share it.
#pragma once

#include "cullproof/methods/methods.hpp"
#include "cullproof/systems/system.hpp"

#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

namespace cullproof {

/// The newest protocol version this cullproof speaks (1, methods only, and 2, with systems, are
/// still read; 3 adds the binary encoding of method frames).
constexpr int kProtocolVersion = 3;

// Limits on what the program writes. A line past one is the program's fault, reported like the
// others (naming the program, the message awaited and the limit) as soon as the line passes it:
// cullproof neither waits for the rest nor keeps more than the limit and one read (64 KiB).

/// Bytes of the handshake line (room for hundreds of methods with long descriptions).
constexpr std::size_t kMaxHandshakeBytes = std::size_t(1) << 20;  // 1 MiB
/// Bytes of the answer to a frame of n volumes: kMaxAnswerBytes + n * kMaxAnswerBytesPerVolume.
/// A verdict written tightly takes 15 bytes ("intersecting",), so a frame of 1,024 volumes
/// (VerifyOptions::frame_size, as cullproof times a method) answers in about 15 KiB, against a
/// limit of 128 KiB; the fixed part holds "frame", "ns" and an "error" text.
constexpr std::size_t kMaxAnswerBytes = std::size_t(64) << 10;  // 64 KiB
constexpr std::size_t kMaxAnswerBytesPerVolume = 64;
/// Arrays and objects nested in a message (a handshake nests 3 deep, an answer 2).
constexpr int kMaxProtocolDepth = 64;

struct ExternalOptions {
  std::vector<std::string> command;  ///< the program and its arguments (run without a shell)
  /// How long cullproof waits for each answer before calling the program hung.
  std::chrono::milliseconds timeout{10000};
  /// How long cullproof waits for the handshake (a program that loads an engine may take a while).
  std::chrono::milliseconds handshake_timeout{30000};
  /// Copies of the program to run side by side (at least 1): the campaign's threads ask whichever
  /// is free, so round trips overlap. A stateful method is always asked through the first copy,
  /// which sees its frames in order. Every copy must offer the same methods.
  int instances = 1;
};

/// Starts the program, reads its handshake and returns its methods (origin user unless the
/// handshake says otherwise). Every call into a method sends one message and waits for its
/// answer: a frame in JSON, or in the binary encoding (version 3) the frames of a call, and of a
/// classify_frames call many frames (Method::has_frames, not for a stateful method); a program that exits, hangs past the timeout, or answers what the protocol does not
/// allow (malformed JSON, another frame, the wrong count, an unknown verdict, a line or nesting
/// past the limits above) makes the call throw
/// std::runtime_error naming the program, the message and what was wrong (the campaign makes it
/// that method's MethodFault, with the case saved). The program is then stopped, and the next call
/// starts it again (the same handshake required; a stateful method's next frame resets it), so
/// its other methods go on. Throws std::runtime_error when the program cannot be started or its
/// handshake is not one this version reads.
std::vector<Method> external_methods(const ExternalOptions& options);

/// Starts the program (one copy: a system's state lives in it), reads its handshake (version 2)
/// and returns its culling systems. Building a system sends the scene (the objects of the kinds
/// it declared) and waits for it to be built; a later build of the same system replaces the
/// program's scene (cullproof runs one scene at a time per system). update() and cull() send one
/// message each and wait for the answer. A fault (exit, hang, an answer the protocol does not
/// allow) makes the phase throw std::runtime_error naming the program, the message and what was
/// wrong; the judge turns it into a SystemFault.
std::vector<System> external_systems(const ExternalOptions& options);

}  // namespace cullproof
