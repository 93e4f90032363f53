#pragma once
// A real X server without a screen for tests of windows: Xvfb on a display number it picks
// itself (-displayfd), screenshots of the root window (xwd, converted by ImageMagick), keys
// through xdotool, and programs run in the background against it. A test checks available()
// first and skips, saying what is missing, when any of these tools is not installed.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace rostro::test {

inline bool on_path(const std::string& tool) {
  return std::system(("command -v " + tool + " > /dev/null 2>&1").c_str()) == 0;
}

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs `command` through sh; stdout and stderr together.
inline std::string shell(const std::string& command, int* exit_code = nullptr) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  std::string out;
  char buffer[4096];
  while (pipe != nullptr && std::fgets(buffer, sizeof buffer, pipe) != nullptr) out += buffer;
  const int status = pipe != nullptr ? pclose(pipe) : -1;
  if (exit_code != nullptr) *exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

// A command run by sh in the background, its output going to files.
class Background {
 public:
  Background(const std::string& command, const std::filesystem::path& out,
             const std::filesystem::path& err) {
    pid_ = fork();
    if (pid_ == 0) {
      setpgid(0, 0);
      const int o = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int e = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      dup2(o, 1);
      dup2(e, 2);
      execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
  }
  ~Background() {
    if (pid_ > 0 && !exited_) {
      kill(-pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  Background(const Background&) = delete;
  Background& operator=(const Background&) = delete;

  // The exit code once it ended within `timeout`; -1 if it is still running.
  int wait_for(std::chrono::seconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!exited_) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exited_ = true;
        code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        break;
      }
      if (std::chrono::steady_clock::now() > end) return -1;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return code_;
  }
  bool running() { return wait_for(std::chrono::seconds(0)) == -1; }

 private:
  pid_t pid_ = -1;
  bool exited_ = false;
  int code_ = -1;
};

// Waits until `file` contains `text` at least `times` times; false after `timeout`.
inline bool wait_for_text(const std::filesystem::path& file, const std::string& text,
                          std::chrono::seconds timeout, int times = 1) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    const std::string s = read_text(file);
    int found = 0;
    for (auto p = s.find(text); p != std::string::npos; p = s.find(text, p + 1)) ++found;
    if (found >= times) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return false;
}

class XDisplay {
 public:
  // What is missing for window tests, or "" when Xvfb, xdotool, xwd and convert are there.
  static std::string missing_tools() {
    std::string missing;
    for (const char* tool : {"Xvfb", "xdotool", "xwd", "convert"}) {
      if (!on_path(tool)) missing += std::string(missing.empty() ? "" : ", ") + tool;
    }
    return missing;
  }

  // Starts Xvfb with one 1280x800 24-bit screen; name() is empty if it did not start.
  XDisplay() {
    int fds[2];
    if (pipe(fds) != 0) return;
    pid_ = fork();
    if (pid_ == 0) {
      close(fds[0]);
      const int devnull = open("/dev/null", O_WRONLY);
      dup2(devnull, 1);
      dup2(devnull, 2);
      const std::string fd = std::to_string(fds[1]);
      execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1280x800x24", "-nolisten",
             "tcp", static_cast<char*>(nullptr));
      _exit(127);
    }
    close(fds[1]);
    std::string number;
    char c = 0;
    while (read(fds[0], &c, 1) == 1 && c != '\n') number += c;
    close(fds[0]);
    if (!number.empty()) name_ = ":" + number;
  }
  ~XDisplay() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      waitpid(pid_, nullptr, 0);
    }
  }
  XDisplay(const XDisplay&) = delete;
  XDisplay& operator=(const XDisplay&) = delete;

  const std::string& name() const { return name_; }
  // "DISPLAY=:N " to put before a command.
  std::string env() const { return "DISPLAY=" + name_ + " "; }

  // The id of the first window whose title contains `title`; "" after `timeout`.
  std::string find_window(const std::string& title, std::chrono::seconds timeout) const {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
      int code = 0;
      std::string id = shell(env() + "xdotool search --name '" + title + "'", &code);
      if (code == 0 && !id.empty()) return id.substr(0, id.find('\n'));
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    return "";
  }
  // Gives `window` the keyboard and types `key` (an X keysym name: c, q, space, Right).
  void key(const std::string& window, const std::string& key) const {
    shell(env() + "xdotool windowfocus --sync " + window + " key " + key);
  }
  // The title of `window` as it is now.
  std::string title(const std::string& window) const {
    return shell(env() + "xdotool getwindowname " + window);
  }
  // The title of `window` once `accept` takes it, or the last one read after `timeout`: a
  // key's effect shows on the next frame drawn, later on a loaded machine.
  template <class Accept>
  std::string wait_for_title(const std::string& window, Accept accept,
                             std::chrono::seconds timeout) const {
    const auto end = std::chrono::steady_clock::now() + timeout;
    std::string now = title(window);
    while (!accept(now) && std::chrono::steady_clock::now() < end) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      now = title(window);
    }
    return now;
  }
  // Writes the whole screen to a PNG; false if xwd or convert failed.
  bool screenshot(const std::filesystem::path& png) const {
    int code = 0;
    shell(env() + "xwd -root -silent | convert xwd:- png:" + png.string(), &code);
    return code == 0 && std::filesystem::exists(png);
  }

 private:
  pid_t pid_ = -1;
  std::string name_;
};

}  // namespace rostro::test
