// Cullers in any language: a program that speaks the cullproof process protocol (JSON Lines over
// its stdin and stdout, docs/protocol.md) becomes a Method like any other, verified, shrunk and
// recorded the same way. The program is started once; its methods share it.
#pragma once

#include "cullproof/methods.hpp"

#include <chrono>
#include <string>
#include <vector>

namespace cullproof {

/// The protocol version this cullproof speaks.
constexpr int kProtocolVersion = 1;

struct ExternalOptions {
  std::vector<std::string> command;  ///< the program and its arguments (run without a shell)
  /// How long cullproof waits for the handshake and for each answer before calling the program hung.
  std::chrono::milliseconds timeout{10000};
  /// Copies of the program to run side by side (at least 1): the campaign's threads ask whichever
  /// is free, so round trips overlap. A stateful method is always asked through the first copy,
  /// which sees its frames in order. Every copy must offer the same methods.
  int instances = 1;
};

/// Starts the program, reads its handshake and returns its methods (origin user unless the
/// handshake says otherwise). Every call into a method sends one frame message and waits for its
/// answer; a program that exits, hangs past the timeout, or answers what the protocol does not
/// allow (malformed JSON, another frame, the wrong count, an unknown verdict) makes the call throw
/// std::runtime_error naming the program, the message and what was wrong (the campaign turns it
/// into a MethodFault, with the case saved). Throws std::runtime_error when the program cannot be
/// started or its handshake is not one this version reads.
std::vector<Method> external_methods(const ExternalOptions& options);

}  // namespace cullproof
