// The program's subcommands. Each adds its options to the CLI11 app, bound to the fields of its
// struct (which must outlive the parse), and runs from them; main.cpp only parses and dispatches.
#pragma once

#include "cullproof/methods.hpp"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>
#include <vector>

#ifdef CULLPROOF_HAVE_ORACLE
#include "cullproof/campaign.hpp"
#endif

namespace cullproof::app {

/// A program under test through the process protocol (docs/protocol.md):
/// --external NAME ... -- PROGRAM ARGS.
struct ExternalProgram {
  std::vector<std::string> names;    ///< --external (repeatable; 'all': every method it offers)
  std::vector<std::string> command;  ///< everything after the first '--'
  int timeout_ms = 10000;            ///< --external-timeout
  int jobs = 1;                      ///< --external-jobs (verify)
  /// Adds --external, --external-timeout and --external-jobs to cmd.
  void add_options(CLI::App* cmd);
  /// The program's methods named by --external beside the built-in ones named in `builtin`, or
  /// the built-in ones alone; std::invalid_argument when a name or the program is missing.
  std::vector<Method> methods(const std::vector<std::string>& builtin, int instances = 1) const;
};

/// `methods [--json]`.
struct MethodsCommand {
  CLI::App* cmd = nullptr;
  bool json = false;
};
void add_methods(CLI::App& app, MethodsCommand& c);
int run_methods_command(const MethodsCommand& c);

/// `classify FILE... [--method NAME ...] [--no-oracle]`.
struct ClassifyCommand {
  CLI::App* cmd = nullptr;
  std::vector<std::string> files, methods;
  bool no_oracle = false;
};
void add_classify(CLI::App& app, ClassifyCommand& c);
int run_classify_command(const ClassifyCommand& c, const ExternalProgram& external);

#ifdef CULLPROOF_HAVE_ORACLE
/// `verify ...`: the side-by-side run.
struct VerifyCommand {
  CLI::App* cmd = nullptr;
  CLI::Option* index_option = nullptr;
  VerifyOptions options;
  std::vector<std::string> distributions;
  std::string json_file, corpus_dir = "corpus";
  bool no_corpus = false, no_progress = false;
  std::uint64_t index = 0;
};
void add_verify(CLI::App& app, VerifyCommand& c, ExternalProgram& external);
int run_verify_command(VerifyCommand& c, const ExternalProgram& external);

/// `corpus list|show ID|replay|rerecord METHOD ...`.
struct CorpusCommand {
  CLI::App* cmd = nullptr;
  std::string action, id, dir = "corpus";
  bool strict = false;
  std::string html, svg, zoom_svg;  ///< show: the case drawn (with the report)
};
void add_corpus(CLI::App& app, CorpusCommand& c, ExternalProgram& external);
int run_corpus_command(const CorpusCommand& c, const ExternalProgram& external);
#endif

}  // namespace cullproof::app
