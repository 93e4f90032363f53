// `rostro shoot`: a whole shoot from a manifest. Wiring only: it runs Snakemake on the
// repository's workflow (workflow/Snakefile, docs/shoot.md), which calibrates each actor once
// and runs `rostro capture` and the checks per take; rostro itself stays a one-take program.

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "apps/commands.hpp"
#include "apps/interrupt.hpp"
#include "facecore/error.hpp"

extern char** environ;

namespace rostro::app {
namespace {

namespace fs = std::filesystem;

struct ShootArgs {
  std::string manifest, out, profile;
  int jobs = 1;
  bool dry_run = false;
  std::vector<std::string> config;
};

// The first executable `name` on PATH, or "" when there is none.
std::string find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return {};
  const std::string dirs = path;
  for (std::size_t start = 0; start <= dirs.size();) {
    const std::size_t end = std::min(dirs.find(':', start), dirs.size());
    const fs::path candidate = fs::path(end > start ? dirs.substr(start, end - start) : ".") / name;
    if (::access(candidate.c_str(), X_OK) == 0 && !fs::is_directory(candidate))
      return candidate.string();
    start = end + 1;
  }
  return {};
}

// workflow/ of the source tree this program was built from ($ROSTRO_WORKFLOW overrides).
fs::path workflow_dir() {
  if (const char* env = std::getenv("ROSTRO_WORKFLOW"); env != nullptr && *env != '\0') return env;
  return ROSTRO_WORKFLOW_DIR;
}

// Runs `argv` and waits for it; a signal to rostro is passed on once, and Snakemake then
// stops its jobs (finished takes stay). Returns the exit status, or 128 + the signal.
int run_and_wait(const std::vector<std::string>& argv, InterruptScope& interrupt) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  if (const int err = posix_spawn(&pid, args[0], nullptr, nullptr, args.data(), environ); err != 0)
    throw InputError(argv[0] + ": cannot run: " + std::strerror(err));
  bool forwarded = false;
  for (;;) {
    int status = 0;
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) {
      if (WIFEXITED(status)) return WEXITSTATUS(status);
      return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    }
    if (done < 0 && errno != EINTR) throw InputError(argv[0] + ": lost track of the process");
    if (interrupt.requested() && !forwarded) {
      ::kill(pid, SIGINT);  // Snakemake's own way to stop: it ends the running jobs cleanly
      forwarded = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

void run_shoot(const ShootArgs& a) {
  if (!fs::is_regular_file(a.manifest)) throw InputError(a.manifest + ": no such manifest file");
  if (a.jobs < 1) throw InputError("-j " + std::to_string(a.jobs) + ": expected 1 or more");
  const std::string snakemake = find_on_path("snakemake");
  if (snakemake.empty())
    throw InputError(
        "snakemake not found on PATH: install it with 'apt-get install snakemake' (Debian 12: "
        "7.21; scripts/install-deps.sh does)");
  const fs::path snakefile = workflow_dir() / "Snakefile";
  if (!fs::is_regular_file(snakefile))
    throw InputError(snakefile.string() +
                     ": the shoot workflow is missing (set ROSTRO_WORKFLOW "
                     "to the repository's workflow/ folder)");
  const fs::path out =
      a.out.empty() ? fs::path("out") / fs::path(a.manifest).stem() : fs::path(a.out);
  fs::create_directories(out);
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);

  std::vector<std::string> argv = {snakemake,    "--snakefile",  snakefile.string(),  "--directory",
                                   out.string(), "--keep-going", "--rerun-incomplete"};
  if (a.profile.empty()) {
    argv.insert(argv.end(), {"--cores", std::to_string(a.jobs)});
  } else {
    argv.insert(argv.end(), {"--profile", a.profile, "--jobs", std::to_string(a.jobs)});
  }
  if (a.dry_run) argv.push_back("--dry-run");
  argv.insert(argv.end(), {"--config", "manifest=" + fs::absolute(a.manifest).string()});
  if (!ec) argv.push_back("rostro=" + self.string());
  for (const std::string& c : a.config) {
    if (c.find('=') == std::string::npos)
      throw InputError("--config " + c + ": expected KEY=VALUE (workflow/config.yaml)");
    argv.push_back(c);
  }

  InterruptScope interrupt;
  const int status = run_and_wait(argv, interrupt);
  const fs::path report = out / "report.md";
  if (interrupt.requested()) {
    std::fprintf(stderr,
                 "rostro: shoot stopped by %s: finished takes are kept in %s; the same command "
                 "resumes with the rest\n",
                 interrupt.signal_name().c_str(), out.c_str());
    std::exit(128 + (status > 128 ? status - 128 : SIGINT));
  }
  if (status != 0)
    throw InputError(
        "shoot " + a.manifest + ": snakemake exited with status " + std::to_string(status) +
        (fs::exists(report) ? "; each failed take's row in " + report.string() + " says why"
                            : "; see its messages above"));
  if (!a.dry_run) std::printf("%s: the shoot report\n", report.c_str());
}

}  // namespace

void add_shoot_commands(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "shoot", "Capture a whole shoot from a manifest (Snakemake: resumable, locally or on Slurm)");
  static ShootArgs a;
  cmd->add_option("MANIFEST", a.manifest,
                  "Shoot manifest CSV: take,actor,source,layout,camera,neutral,options")
      ->required();
  cmd->add_option("-j,--jobs", a.jobs, "Cores to use (with --profile: jobs in the queue at once)")
      ->capture_default_str();
  cmd->add_option("-o,--out", a.out, "Output folder (default: out/MANIFEST_NAME)");
  cmd->add_option("--profile", a.profile,
                  "A Snakemake profile folder, e.g. workflow/profiles/slurm to submit to Slurm");
  cmd->add_flag("-n,--dry-run", a.dry_run, "List the jobs that would run, run none");
  cmd->add_option("--config", a.config,
                  "KEY=VALUE for the workflow (workflow/config.yaml: take_threads, checks...)");
  cmd->footer(
      "Runs snakemake on workflow/Snakefile (Debian's snakemake 7.21): each actor is "
      "calibrated\nonce, every take is captured (.fap, tracks, preview) and checked, and "
      "OUT/report.md and\nOUT/report-fps.png list every take. Run it again after a crash or a "
      "change: only missing\nor changed takes are redone. A failing take is reported and does "
      "not stop the others\n(exit 1 then). Manifest format: docs/shoot.md.\n\n"
      "Example:\n  rostro shoot data/shoot/example.csv -j 2 -o out/example-shoot");
  cmd->callback([] { run_shoot(a); });
}

}  // namespace rostro::app
