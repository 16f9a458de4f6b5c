// POV-Ray 3.7 scene pieces shared by the exporters, and running povray headless.
#include "ifsforge/io/povray.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/io/atomic_file.h"

namespace ifsforge {
namespace {

// The master copy is povray/ifsforge.inc in the sources; a test keeps the two identical.
const char kIfsforgeInc[] = R"IFSFORGE_INC(
// ifsforge.inc: POV-Ray 3.7 support for the scenes ifsforge writes.
//
// Scenes written by `ifsforge instances ... --pov scene.pov` include this file, and a copy of it
// is written beside every scene (replacing the one there), so `povray +Iscene.pov` needs no
// library path. Keep your changes in the scene, not in that copy. This copy in the ifsforge
// sources is the documented master; the library writes the same bytes.
//
// PRIMITIVES
// Each primitive lives in the frame of its instance (the vector of seed 5.8.2): x runs along
// the instance's vector q0 -> qh, y and z complete the frame, and one unit is the vector's
// length d. A scene places a primitive with
//     object { IFS_Cone matrix <d*e1, d*e2, d*e3, q0> pigment { rgb <r, g, b> } }
// (POV-Ray's matrix rows are the images of x, y and z, then the translation). Spheres are
// written as  sphere { q0, d pigment {...} }, the same as IFS_Sphere placed that way, because
// POV-Ray parses the plain form fastest.
//   3D, centred on the origin and inside the unit ball (d is the bounding radius):
//     IFS_Sphere     radius 1
//     IFS_Box        the cube inscribed in the unit ball, edges along the frame
//     IFS_Cone       apex at x = 1, base circle at x = -1/2 of radius sqrt(3)/2
//     IFS_Cylinder   along x, half-length = radius = 1/sqrt(2)
//     IFS_Torus      around z, radii 0.75 and 0.25
//   2D, flat in the xy plane (seed 6.1.3.5): the vector is the line, the circle's radius, or
//   the base edge of the triangle (Eq. 95: the third vertex turns by 120 degrees) and square:
//     IFS_Line  IFS_Circle  IFS_Circle_Outline  IFS_Triangle  IFS_Triangle_Outline
//     IFS_Square  IFS_Square_Outline        (lines and outlines are IFS_Stroke wide)
// To replace a primitive, declare it before the #include line of the scene, e.g.
//     #declare IFS_Cone = object { MyLeaf }
//
// LOOK
//   IFS_Finish                              finish of every instance (set with #default)
//   IFS_Key_Light(Position, Size, Quality)  the main light; Size: area-light extent (Quality 2)
//   IFS_Fill_Light(Position)                a dim shadowless light from the other side
//   IFS_Floor(Height, Spacing)              a checkered plane z = Height
//   IFS_Sky()                               a sky sphere graded along +z
// Quality: 0 draft (no shadows), 1 normal, 2 high (soft shadows; the scene adds radiosity).
// The scenes use z as the up axis and the coordinates of the IFS unchanged.

#ifndef (IFS_Inc_Temp)
#declare IFS_Inc_Temp = version;
#version 3.7;

#ifndef (IFS_Stroke) #declare IFS_Stroke = 0.06; #end

#ifndef (IFS_Sphere)   #declare IFS_Sphere = sphere { <0, 0, 0>, 1 } #end
#ifndef (IFS_Box)      #declare IFS_Box = box { -<1, 1, 1> / sqrt(3), <1, 1, 1> / sqrt(3) } #end
#ifndef (IFS_Cone)     #declare IFS_Cone = cone { <-0.5, 0, 0>, sqrt(3) / 2, <1, 0, 0>, 0 } #end
#ifndef (IFS_Cylinder) #declare IFS_Cylinder = cylinder { -<1, 0, 0> / sqrt(2), <1, 0, 0> / sqrt(2), 1 / sqrt(2) } #end
#ifndef (IFS_Torus)    #declare IFS_Torus = torus { 0.75, 0.25 rotate 90 * x } #end

// The outlines are bands of width IFS_Stroke centred on the edges: the shape grown and shrunk
// about its incentre C (inradius R) by half the stroke.
#macro IFS_Grown(V, C, R, Offset) (C + (V - C) * (R + Offset) / R) #end

#ifndef (IFS_Line)
  #declare IFS_Line = polygon { 5, <0, -IFS_Stroke / 2, 0>, <1, -IFS_Stroke / 2, 0>, <1, IFS_Stroke / 2, 0>,
                                   <0, IFS_Stroke / 2, 0>, <0, -IFS_Stroke / 2, 0> }
#end
#ifndef (IFS_Circle) #declare IFS_Circle = disc { <0, 0, 0>, z, 1 } #end
#ifndef (IFS_Circle_Outline)
  #declare IFS_Circle_Outline = disc { <0, 0, 0>, z, 1 + IFS_Stroke / 2, 1 - IFS_Stroke / 2 }
#end
#declare IFS_T0 = <0, 0, 0>;
#declare IFS_T1 = <1, 0, 0>;
#declare IFS_T2 = <0.5, sqrt(3) / 2, 0>;
#declare IFS_TC = <0.5, sqrt(3) / 6, 0>;
#declare IFS_TR = sqrt(3) / 6;
#ifndef (IFS_Triangle) #declare IFS_Triangle = polygon { 4, IFS_T0, IFS_T1, IFS_T2, IFS_T0 } #end
#ifndef (IFS_Triangle_Outline)
  #declare IFS_Triangle_Outline = polygon { 8,
    IFS_Grown(IFS_T0, IFS_TC, IFS_TR, IFS_Stroke / 2), IFS_Grown(IFS_T1, IFS_TC, IFS_TR, IFS_Stroke / 2),
    IFS_Grown(IFS_T2, IFS_TC, IFS_TR, IFS_Stroke / 2), IFS_Grown(IFS_T0, IFS_TC, IFS_TR, IFS_Stroke / 2),
    IFS_Grown(IFS_T0, IFS_TC, IFS_TR, -IFS_Stroke / 2), IFS_Grown(IFS_T1, IFS_TC, IFS_TR, -IFS_Stroke / 2),
    IFS_Grown(IFS_T2, IFS_TC, IFS_TR, -IFS_Stroke / 2), IFS_Grown(IFS_T0, IFS_TC, IFS_TR, -IFS_Stroke / 2) }
#end
#declare IFS_S0 = <0, 0, 0>;
#declare IFS_S1 = <1, 0, 0>;
#declare IFS_S2 = <1, 1, 0>;
#declare IFS_S3 = <0, 1, 0>;
#declare IFS_SC = <0.5, 0.5, 0>;
#ifndef (IFS_Square) #declare IFS_Square = polygon { 5, IFS_S0, IFS_S1, IFS_S2, IFS_S3, IFS_S0 } #end
#ifndef (IFS_Square_Outline)
  #declare IFS_Square_Outline = polygon { 10,
    IFS_Grown(IFS_S0, IFS_SC, 0.5, IFS_Stroke / 2), IFS_Grown(IFS_S1, IFS_SC, 0.5, IFS_Stroke / 2),
    IFS_Grown(IFS_S2, IFS_SC, 0.5, IFS_Stroke / 2), IFS_Grown(IFS_S3, IFS_SC, 0.5, IFS_Stroke / 2),
    IFS_Grown(IFS_S0, IFS_SC, 0.5, IFS_Stroke / 2),
    IFS_Grown(IFS_S0, IFS_SC, 0.5, -IFS_Stroke / 2), IFS_Grown(IFS_S1, IFS_SC, 0.5, -IFS_Stroke / 2),
    IFS_Grown(IFS_S2, IFS_SC, 0.5, -IFS_Stroke / 2), IFS_Grown(IFS_S3, IFS_SC, 0.5, -IFS_Stroke / 2),
    IFS_Grown(IFS_S0, IFS_SC, 0.5, -IFS_Stroke / 2) }
#end

#ifndef (IFS_Finish)
  #declare IFS_Finish = finish { ambient 0.08 diffuse 0.75 specular 0.25 roughness 0.02 }
#end

#macro IFS_Key_Light(Position, Size, Quality)
  light_source { Position, rgb 1
    #if (Quality = 0) shadowless #end
    #if (Quality = 2) area_light <Size, 0, 0>, <0, Size, 0>, 5, 5 adaptive 1 jitter circular orient #end
  }
#end

#macro IFS_Fill_Light(Position)
  light_source { Position, rgb 0.35 shadowless }
#end

#macro IFS_Floor(Height, Spacing)
  plane { z, Height
    pigment { checker rgb <0.82, 0.80, 0.76>, rgb <0.70, 0.68, 0.64> scale Spacing }
    finish { ambient 0.1 diffuse 0.7 }
  }
#end

#macro IFS_Sky()
  sky_sphere {
    pigment { gradient z color_map { [0 rgb <0.92, 0.95, 1.0>] [1 rgb <0.45, 0.62, 0.90>] } scale 2 translate -z }
  }
#end

#version IFS_Inc_Temp;
#end
)IFSFORGE_INC";

std::string vector_text(const PovVector& v) {
  char buffer[64];
  char* end = pov_vector(buffer, static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]));
  return std::string(buffer, end);
}

std::string number_text(double v) {
  char buffer[32];
  return std::string(buffer, pov_number(buffer, static_cast<float>(v)));
}

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

char* pov_number(char* out, float value) {
  if (!std::isfinite(value) || value == 0.0f) {
    *out++ = '0';
    return out;
  }
  return std::to_chars(out, out + 16, value).ptr;
}

char* pov_vector(char* out, float x, float y, float z) {
  *out++ = '<';
  out = pov_number(out, x);
  *out++ = ',';
  out = pov_number(out, y);
  *out++ = ',';
  out = pov_number(out, z);
  *out++ = '>';
  return out;
}

char* pov_unit(char* out, float value) {
  int v = static_cast<int>(std::lround(std::clamp(std::isfinite(value) ? value : 0.0f, 0.0f, 1.0f) * 1000.0f));
  if (v >= 1000) {
    *out++ = '1';
    return out;
  }
  if (v == 0) {
    *out++ = '0';
    return out;
  }
  *out++ = '.';
  const char digits[3] = {char('0' + v / 100), char('0' + v / 10 % 10), char('0' + v % 10)};
  int used = 3;
  while (used > 1 && digits[used - 1] == '0') --used;
  for (int i = 0; i < used; ++i) *out++ = digits[i];
  return out;
}

PovQuality parse_pov_quality(const std::string& text) {
  if (text == "draft") return PovQuality::Draft;
  if (text == "normal") return PovQuality::Normal;
  if (text == "high") return PovQuality::High;
  throw InputError("unknown POV-Ray quality '" + text + "': choose draft, normal or high");
}

const char* to_string(PovQuality q) {
  return q == PovQuality::Draft ? "draft" : q == PovQuality::High ? "high" : "normal";
}

std::string pov_preamble(const std::string& title, const std::string& extra_comment,
                         const PovFraming& framing, const PovEnvironment& environment, int width, int height) {
  const int quality = environment.quality == PovQuality::Draft ? 0 : environment.quality == PovQuality::High ? 2 : 1;
  std::string s;
  s += "// " + pov_comment(title) + "\n";
  s += pov_comment_lines(extra_comment);
  s += "// Written by ifsforge for POV-Ray 3.7; framed for a " + std::to_string(width) + "x" +
       std::to_string(height) + " image:\n//   povray +I<this file> +W" + std::to_string(width) + " +H" +
       std::to_string(height) + " +A0.3\n";
  s += "#version 3.7;\n#include \"ifsforge.inc\"\n";
  s += "#declare IFS_Title = " + pov_string(title) + ";\n";
  s += "#declare IFS_Quality = " + std::to_string(quality) + ";\n";
  s += "#declare IFS_Centre = " + vector_text(framing.centre) + ";\n";
  s += "#declare IFS_Radius = " + number_text(framing.radius) + ";\n";
  s += "global_settings { assumed_gamma 1.0 max_trace_level 8";
  if (quality == 2)
    s += "\n  radiosity { pretrace_start 0.08 pretrace_end 0.01 count 80 error_bound 0.6 recursion_limit 1"
         " normal on }\n  ambient_light 0";
  s += " }\n";
  const PovCamera& c = framing.camera;
  s += std::string("camera { ") + (c.orthographic ? "orthographic" : "perspective") + "\n  location " +
       vector_text(c.location) + "\n  direction " + vector_text(c.direction) + "\n  right " + vector_text(c.right) +
       "\n  up " + vector_text(c.up) + "\n  sky " + vector_text(c.sky) + "\n  look_at " + vector_text(c.look_at) +
       "\n}\n";
  s += "IFS_Key_Light(" + vector_text(framing.key_light) + ", " + number_text(0.15 * framing.radius) + ", IFS_Quality)\n";
  s += "IFS_Fill_Light(" + vector_text(framing.fill_light) + ")\n";
  if (environment.sky) {
    s += "IFS_Sky()\n";
  } else {
    const auto& b = environment.background;
    s += "background { rgb " + vector_text({b[0], b[1], b[2]}) + " }\n";
  }
  if (environment.floor) s += "IFS_Floor(" + number_text(framing.floor_height) + ", " + number_text(0.25 * framing.radius) + ")\n";
  return s;
}

const std::string& povray_include() {
  static const std::string text(kIfsforgeInc + 1);  // the raw string starts with a line break
  return text;
}

void write_bytes(std::FILE* file, const char* data, std::size_t size, const std::string& path) {
  if (size && std::fwrite(data, 1, size, file) != size)
    throw FileError("cannot write '" + path + "': " + std::strerror(errno));
}

void write_povray_include(const std::string& folder) {
  const std::string path = (folder.empty() ? std::string(".") : folder) + "/ifsforge.inc";
  AtomicFile file(path);
  write_bytes(file.file(), povray_include().data(), povray_include().size(), path);
  file.commit();
}

void render_povray(const std::string& scene, const std::string& image, const PovRenderOptions& options) {
  if (options.width < 1 || options.height < 1 || options.width > 65535 || options.height > 65535)
    throw InputError("the render size must be 1..65535 pixels per side");
  if (access(scene.c_str(), R_OK) != 0) throw FileError("cannot read scene '" + scene + "': " + std::strerror(errno));
  check_writable(image);
  const std::string folder = absolute(folder_of(scene));
  const std::string target = absolute(image);
  static std::atomic<int> counter{0};
  const std::string temporary_name =
      ".ifsforge-render-" + std::to_string(getpid()) + "-" + std::to_string(counter++) + ".png";
  const std::string temporary = folder + "/" + temporary_name;
  if (access(folder.c_str(), W_OK) != 0)
    throw FileError("cannot render '" + scene + "': POV-Ray writes its image in the scene's folder '" + folder +
                    "', which is not writable");

  std::vector<std::string> args = {"povray", "+I" + file_name_of(scene), "+O" + temporary_name,
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
  if (pipe(pipe_fds) != 0) throw FileError(std::string("cannot start povray: ") + std::strerror(errno));
  const pid_t pid = fork();
  if (pid < 0) throw FileError(std::string("cannot start povray: ") + std::strerror(errno));
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
  const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0 && access(temporary.c_str(), R_OK) == 0;
  if (!ok) {
    std::remove(temporary.c_str());
    if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
      throw FileError("cannot run povray: it is not on PATH (Debian: apt-get install povray)");
    throw FileError("POV-Ray failed to render '" + scene + "':" + tail(output, 8));
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
