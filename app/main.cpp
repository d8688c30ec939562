// cullproof: run culling methods and the exact oracle side by side.
//
//   cullproof methods [--json]
//   cullproof classify FILE... [--method NAME ...] [--no-oracle] [--external NAME ... -- PROGRAM ARGS...]
//   cullproof verify [--cases N] [--seed S] [--distribution D ...] [--method M ...] [--threads T]
//                    [--external NAME|all ... [--external-timeout MS] -- PROGRAM ARGS...]
//                    [--corpus DIR | --no-corpus] [--json FILE] [--index I]
//   cullproof corpus list|show ID|replay [--dir DIR] [--strict] [--external NAME|all -- PROGRAM ARGS...]
//   cullproof report [--from FILE | verify's options] [--out FILE] [--corpus DIR | --no-corpus]
//   cullproof simulate [SCENE...] [--exhaustive] [--frames N] [--csv FILE] [--json FILE] [--table1]
//
// Each subcommand lives in its own file (commands.hpp); this one parses and dispatches.
#include "commands.hpp"

#include "cullproof/case_io.hpp"
#ifdef CULLPROOF_HAVE_SIM
#include "cullproof/simulate_cli.hpp"
#endif
#ifdef CULLPROOF_HAVE_REPORT
#include "cullproof/report_cli.hpp"
#endif

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>

using namespace cullproof;
using namespace cullproof::app;

static int run(int argc, char** argv) {
  CLI::App app{"cullproof: proves view-frustum culling correct and shows what correctness costs"};
  app.require_subcommand(1);
  ExternalProgram external;
  MethodsCommand methods;
  add_methods(app, methods);
  ClassifyCommand classify;
  add_classify(app, classify);
#ifdef CULLPROOF_HAVE_ORACLE
  VerifyCommand verify;
  add_verify(app, verify, external);
  CorpusCommand corpus;
  add_corpus(app, corpus, external);
#endif
#ifdef CULLPROOF_HAVE_SIM
  cullproof::sim::SimulateOptions sim_opt;
  auto* simulate_cmd = cullproof::sim::add_simulate_subcommand(app, sim_opt);
#endif
#ifdef CULLPROOF_HAVE_ORACLE
  external.add_options(classify.cmd);
#endif
#ifdef CULLPROOF_HAVE_REPORT
  report::ReportOptions report_opt;
  auto* report_cmd = report::add_report_subcommand(app, report_opt);
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
    if (*methods.cmd) return run_methods_command(methods);
    if (*classify.cmd) return run_classify_command(classify, external);
#ifdef CULLPROOF_HAVE_SIM
    if (*simulate_cmd) return cullproof::sim::run_simulate_command(sim_opt);
#endif
#ifdef CULLPROOF_HAVE_REPORT
    if (*report_cmd) return report::run_report_command(report_opt);
#endif
#ifdef CULLPROOF_HAVE_ORACLE
    if (*verify.cmd) return run_verify_command(verify, external);
    if (*corpus.cmd) return run_corpus_command(corpus, external);
#endif
  } catch (const CaseError& e) {
    std::cerr << "cullproof: " << e.what() << "\n";
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
