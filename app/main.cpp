// cullproof: run culling methods and the exact oracle side by side.
//
//   cullproof methods [--json]
//   cullproof classify FILE... [--method NAME ...] [--no-oracle] [--external NAME ... -- PROGRAM ARGS...]
//   cullproof verify [--cases N] [--seed S] [--distribution D ...] [--method M ...] [--threads T]
//                    [--external NAME|all ... [--external-timeout MS] -- PROGRAM ARGS...]
//                    [--corpus DIR | --no-corpus] [--json FILE] [--index I | --shard K/N]
//   cullproof merge SHARD.json... [--json FILE] [--partial]
//   cullproof corpus list|show ID|replay [--dir DIR] [--strict] [--external NAME|all -- PROGRAM ARGS...]
//   cullproof report [--from FILE | verify's options] [--out FILE] [--corpus DIR | --no-corpus]
//   cullproof simulate [SCENE...] [--exhaustive] [--frames N] [--csv FILE] [--json FILE] [--table1]
//   cullproof systems [--system NAME ...] [--family F ...] [--runs N] [--objects N] [--frames N] [--seed S]
//                     [--index I] [--json FILE] [--corpus DIR | --no-corpus]
//                     [--external NAME|all ... [--external-timeout MS] -- PROGRAM ARGS...]
//
// Each subcommand lives in its own file and declares its options there (commands.hpp); this one
// parses and dispatches. The oracle's subcommands, the report and the simulator are built when
// their libraries are (the CULLPROOF_HAVE_* definitions, app/CMakeLists.txt).
#include "commands.hpp"

#include "cullproof/io/case_io.hpp"

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <functional>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

using namespace cullproof;
using namespace cullproof::app;

static int run(int argc, char** argv) {
  CLI::App app{"cullproof: proves view-frustum culling correct and shows what correctness costs"};
  app.require_subcommand(1);
  ExternalProgram external;
  // Each subcommand: its parsed command and how it runs.
  std::vector<std::pair<CLI::App**, std::function<int()>>> commands;
  MethodsCommand methods;
  add_methods(app, methods);
  commands.emplace_back(&methods.cmd, [&] { return run_methods_command(methods); });
  ClassifyCommand classify;
  add_classify(app, classify);
  commands.emplace_back(&classify.cmd, [&] { return run_classify_command(classify, external); });
#ifdef CULLPROOF_HAVE_ORACLE
  VerifyCommand verify;
  add_verify(app, verify, external);
  commands.emplace_back(&verify.cmd, [&] { return run_verify_command(verify, external); });
  MergeCommand merge;
  add_merge(app, merge);
  commands.emplace_back(&merge.cmd, [&] { return run_merge_command(merge); });
  CorpusCommand corpus;
  add_corpus(app, corpus, external);
  commands.emplace_back(&corpus.cmd, [&] { return run_corpus_command(corpus, external); });
#endif
#ifdef CULLPROOF_HAVE_SCENES
  SystemsCommand systems;
  add_systems(app, systems, external);
  commands.emplace_back(&systems.cmd, [&] { return run_systems_command(systems, external); });
#endif
#ifdef CULLPROOF_HAVE_GPU
  DevicesCommand devices;
  add_devices(app, devices);
  commands.emplace_back(&devices.cmd, [&] { return run_devices_command(devices); });
#endif
#ifdef CULLPROOF_HAVE_SIM
  SimulateCommand simulate;
  add_simulate(app, simulate);
  commands.emplace_back(&simulate.cmd, [&] { return run_simulate_command(simulate); });
#endif
#ifdef CULLPROOF_HAVE_ORACLE
  external.add_options(classify.cmd);
#endif
#ifdef CULLPROOF_HAVE_REPORT
  ReportCommand report;
  add_report(app, report);
  commands.emplace_back(&report.cmd, [&] { return run_report_command(report); });
#endif

  // Everything after the first '--' is the external program's command line, taken before the
  // subcommands' own positional arguments (classify's files) can claim it.
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--") {
      external.command.assign(argv + i + 1, argv + argc);
      argc = i;
      break;
    }
  CLI11_PARSE(app, argc, argv);
  try {
    for (const auto& [cmd, run_command] : commands)
      if (**cmd) return run_command();
  } catch (const CaseError& e) {
    std::cerr << "cullproof: " << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {  // bad input: a name, an option's value
    std::cerr << "cullproof: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "cullproof: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

// The standard output is an output like the others: a write to it that fails (a full disk, a closed
// pipe) is reported, naming it, and the status is non-zero.
int main(int argc, char** argv) {
  const int status = run(argc, argv);
  std::cout.flush();
  if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout) {
    const int err = errno;
    std::cerr << "cullproof: error: cannot write the standard output: " << std::strerror(err) << "\n";
    return status != 0 ? status : 1;
  }
  return status;
}
