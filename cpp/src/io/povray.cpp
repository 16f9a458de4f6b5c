// Running POV-Ray 3.7 headless on a scene.
#include "ifsforge/io/povray.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/io/atomic_file.h"

namespace ifsforge {
namespace {

std::string file_name_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string absolute(const std::string& path) {
  if (!path.empty() && path[0] == '/') return path;
  char cwd[4096];
  if (!getcwd(cwd, sizeof cwd)) throw FileError(std::string("cannot resolve '") + path + "': " + std::strerror(errno));
  return std::string(cwd) + "/" + path;
}

/// A new empty file of a random name `prefix` ... `suffix` in `folder` (create_exclusive);
/// returns its name within the folder.
std::string new_file(const std::string& folder, const std::string& prefix, const std::string& suffix) {
  std::string path;
  close(create_exclusive(folder + "/" + prefix, suffix, 0600, "cannot create a file in '" + folder + "'", path));
  return path.substr(folder.size() + 1);
}

/// The scene under a name of letters and digits beside it: a symbolic link to it, or a copy
/// where the file system has no links.
void alias_scene(const std::string& folder, const std::string& scene, const std::string& alias) {
  const std::string path = folder + "/" + alias;
  std::remove(path.c_str());  // made by new_file: symlink() will not replace it, nor anything planted since
  if (symlink(file_name_of(scene).c_str(), path.c_str()) == 0) return;
  std::FILE* in = std::fopen(scene.c_str(), "rb");
  if (!in) throw FileError("cannot read scene '" + scene + "': " + std::strerror(errno));
  const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW, 0600);
  std::FILE* out = fd < 0 ? nullptr : fdopen(fd, "wb");
  bool ok = out != nullptr;
  char buffer[1 << 16];
  std::size_t got;
  while (ok && (got = std::fread(buffer, 1, sizeof buffer, in)) > 0) ok = std::fwrite(buffer, 1, got, out) == got;
  ok = ok && !std::ferror(in);
  std::fclose(in);
  if (out) ok = std::fclose(out) == 0 && ok;
  else if (fd >= 0) close(fd);
  if (!ok) {
    std::remove(path.c_str());
    throw FileError("cannot copy scene '" + scene + "' for POV-Ray into '" + folder + "'");
  }
}

/// Every occurrence of `from` in `text` replaced by `to`.
std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = 0; (at = text.find(from, at)) != std::string::npos; at += to.size()) text.replace(at, from.size(), to);
  return text;
}

/// The last `lines` non-empty lines of POV-Ray's output, for error messages.
std::string tail(const std::string& text, int lines) {
  std::vector<std::string> kept;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    if (line.find_first_not_of(" \t\r") != std::string::npos &&
        line.find("cannot open the user configuration file") == std::string::npos)
      kept.push_back(line);
    start = end + 1;
  }
  std::string out;
  for (std::size_t i = kept.size() > std::size_t(lines) ? kept.size() - lines : 0; i < kept.size(); ++i)
    out += "\n  " + kept[i];
  return out;
}

}  // namespace

void render_povray(const std::string& scene, const std::string& image, const PovRenderOptions& options) {
  if (options.width < 1 || options.height < 1 || options.width > 65535 || options.height > 65535)
    throw InputError("the render size must be 1..65535 pixels per side");
  if (access(scene.c_str(), R_OK) != 0) throw FileError("cannot read scene '" + scene + "': " + std::strerror(errno));
  check_writable(image);
  const std::string folder = absolute(folder_of(scene));
  const std::string target = absolute(image);
  if (access(folder.c_str(), W_OK) != 0)
    throw FileError("cannot render '" + scene + "': POV-Ray writes its image in the scene's folder '" + folder +
                    "', which is not writable");
  // POV-Ray splits its command line at spaces and reads words starting with + or - as options,
  // whatever the argument list: scene and image reach it by random names of letters and digits.
  const std::string temporary_name = new_file(folder, ".ifsforge-render-", ".png");
  const std::string temporary = folder + "/" + temporary_name;
  std::string alias_name;
  try {
    alias_name = new_file(folder, ".ifsforge-scene-", ".pov");
    alias_scene(folder, scene, alias_name);
  } catch (...) {
    std::remove(temporary.c_str());
    if (!alias_name.empty()) std::remove((folder + "/" + alias_name).c_str());
    throw;
  }
  const std::string alias = folder + "/" + alias_name;
  struct Cleanup {
    std::string path;
    ~Cleanup() { std::remove(path.c_str()); }
  } remove_alias{alias};

  std::vector<std::string> args = {"povray", "+I" + alias_name, "+O" + temporary_name,
                                   "+W" + std::to_string(options.width), "+H" + std::to_string(options.height),
                                   "-D", "+FN", "-P", "-V"};
  if (options.antialias > 0.0) {
    char a[32];
    std::snprintf(a, sizeof a, "+A%.3f", options.antialias);
    args.push_back(a);
  } else {
    args.push_back("-A");
  }
  if (options.threads > 0) args.push_back("+WT" + std::to_string(options.threads));
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  int pipe_fds[2];
  if (pipe(pipe_fds) != 0) {
    std::remove(temporary.c_str());
    throw FileError(std::string("cannot start povray: ") + std::strerror(errno));
  }
  const pid_t pid = fork();
  if (pid < 0) {
    std::remove(temporary.c_str());
    close(pipe_fds[0]);
    close(pipe_fds[1]);
    throw FileError(std::string("cannot start povray: ") + std::strerror(errno));
  }
  if (pid == 0) {
    // Child: only async-signal-safe calls until exec.
    dup2(pipe_fds[1], 1);
    dup2(pipe_fds[1], 2);
    close(pipe_fds[0]);
    close(pipe_fds[1]);
    if (chdir(folder.c_str()) != 0) _exit(126);
    execvp("povray", argv.data());
    _exit(127);
  }
  close(pipe_fds[1]);
  fcntl(pipe_fds[0], F_SETFL, O_NONBLOCK);
  std::string output;
  int status = 0;
  bool cancelled = false;
  for (;;) {
    pollfd p{pipe_fds[0], POLLIN, 0};
    poll(&p, 1, 50);
    char buffer[4096];
    ssize_t got;
    while ((got = read(pipe_fds[0], buffer, sizeof buffer)) > 0) output.append(buffer, static_cast<std::size_t>(got));
    const pid_t done = waitpid(pid, &status, WNOHANG);
    if (done == pid) {
      while ((got = read(pipe_fds[0], buffer, sizeof buffer)) > 0) output.append(buffer, static_cast<std::size_t>(got));
      break;
    }
    bool go_on = true;
    if (options.progress) {
      try {
        go_on = options.progress(0.0);
      } catch (...) {
        kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
        close(pipe_fds[0]);
        std::remove(temporary.c_str());
        throw;
      }
    }
    if (!go_on) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      cancelled = true;
      break;
    }
  }
  close(pipe_fds[0]);
  if (cancelled) {
    std::remove(temporary.c_str());
    throw Cancelled();
  }
  struct stat written {};
  const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0 && stat(temporary.c_str(), &written) == 0 &&
                  written.st_size > 0;
  if (!ok) {
    std::remove(temporary.c_str());
    if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
      throw FileError("cannot run povray: it is not on PATH (Debian: apt-get install povray)");
    throw FileError("POV-Ray failed to render '" + scene + "':" + replace_all(tail(output, 8), alias_name, file_name_of(scene)));
  }
  if (std::rename(temporary.c_str(), target.c_str()) != 0) {
    // Another file system: copy through an atomic write, then drop the temporary.
    const int saved = errno;
    std::FILE* in = std::fopen(temporary.c_str(), "rb");
    if (!in) throw FileError("cannot move the render to '" + image + "': " + std::strerror(saved));
    try {
      AtomicFile out(target);
      char buffer[1 << 16];
      std::size_t got;
      while ((got = std::fread(buffer, 1, sizeof buffer, in)) > 0) write_bytes(out.file(), buffer, got, image);
      out.commit();
    } catch (...) {
      std::fclose(in);
      std::remove(temporary.c_str());
      throw;
    }
    std::fclose(in);
    std::remove(temporary.c_str());
  }
  if (options.progress) options.progress(1.0);
}

}  // namespace ifsforge
