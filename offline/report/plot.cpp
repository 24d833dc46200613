// SPDX-License-Identifier: BSD-3-Clause
#include "offline/report/plot.hpp"

#include <spawn.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <utility>

#include "offline/report/csv_writer.hpp"
#include "plant/lti/frequency_response.hpp"

extern char** environ;

namespace flexloop::report {

namespace {

// gnuplot string. Single-quoted (no escapes except '' for a quote) unless the text has line
// breaks: a double-quoted string then, where "\n" breaks the line (a title of two lines).
std::string quote(const std::string& s) {
  if (s.find('\n') != std::string::npos) {
    std::string q = "\"";
    for (char c : s) {
      if (c == '\\' || c == '"')
        q += std::string("\\") + c;
      else if (c == '\n')
        q += "\\n";
      else if (c != '\r')
        q += c;
    }
    return q + "\"";
  }
  std::string q = "'";
  for (char c : s) {
    if (c == '\'')
      q += "''";
    else if (c == '\n' || c == '\r')
      q += ' ';
    else
      q += c;
  }
  return q + "'";
}

std::string checked_style(const std::string& style, const std::string& fallback,
                          const std::string& png_path) {
  if (style.empty()) return fallback;
  for (char c : style) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    std::strchr(" .#'\"-_:", c) != nullptr;
    if (!ok || c == '\0')
      throw std::invalid_argument("plot " + png_path + ": style '" + style +
                                  "' contains the character '" + std::string(1, c) +
                                  "'; only a gnuplot `with` clause is allowed");
  }
  return style;
}

bool has_colour(const std::string& style) {
  for (const char* key : {"lc ", "linecolor", "lt ", "linetype"})
    if (style.find(key) != std::string::npos) return true;
  return false;
}

// A value gnuplot can place on the axis, else NaN (a gap in the line).
std::string value(double v, bool log_axis) {
  if (!std::isfinite(v) || (log_axis && v <= 0.0)) return "NaN";
  return format_number(v);
}

std::string or_default(const std::string& s, const char* fallback) {
  return s.empty() ? fallback : s;
}

// Common preamble: terminal, output, labels, axes.
std::string preamble(const PlotSpec& spec, const std::string& out_png) {
  if (spec.width_px < 100 || spec.height_px < 100 || spec.width_px > 10000 ||
      spec.height_px > 10000)
    throw std::invalid_argument("plot: image size " + std::to_string(spec.width_px) + "x" +
                                std::to_string(spec.height_px) + " px out of range");
  const std::string size = std::to_string(spec.width_px) + "," + std::to_string(spec.height_px);
  std::ostringstream s;
  s << "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
    << "  set terminal pngcairo noenhanced size " << size << " font 'sans,11'\n"
    << "} else {\n"
    << "  set terminal png noenhanced size " << size << "\n"
    << "}\n"
    << "set output " << quote(out_png) << "\n"
    << "set encoding utf8\n"
    << "set grid xtics ytics mxtics mytics lw 1 lc rgb '#b8b8b8', lw 1 lc rgb '#e0e0e0'\n"
    // Under the plot: never over a curve, however many channels; its box clear of the x label.
    << "set key below box height 0.6\n"
    << "set autoscale xfix\n"  // the axis ends where the data do (a spectrum at its Nyquist)
    << "set datafile missing 'NaN'\n";
  return s.str();
}

std::string labels(const PlotSpec& spec) {
  std::ostringstream s;
  s << "set title " << quote(spec.title) << "\n"
    << "set xlabel " << quote(spec.xlabel) << "\n"
    << "set ylabel " << quote(spec.ylabel) << "\n"
    << (spec.logx ? "set logscale x\n" : "unset logscale x\n")
    << (spec.logy ? "set logscale y\n" : "unset logscale y\n");
  if (spec.x_max > spec.x_min)
    s << "set xrange [" << format_number(spec.x_min) << ":" << format_number(spec.x_max) << "]\n";
  return s.str();
}

std::string datablock(const std::string& name, const std::vector<double>& x,
                      const std::vector<std::vector<double>>& ys, bool logx, bool logy) {
  std::string s = name + " << EOD\n";
  for (std::size_t i = 0; i < x.size(); ++i) {
    s += value(x[i], logx);
    for (const auto& y : ys) s += ' ' + value(y[i], logy);
    s += '\n';
  }
  return s + "EOD\n";
}

// The end of gnuplot's complaints, for an error message.
std::string tail(const std::string& said) {
  constexpr std::size_t kMax = 2000;
  return said.size() > kMax ? "..." + said.substr(said.size() - kMax) : said;
}

struct TempFile {
  std::string path;
  explicit TempFile(const std::string& base, const std::string& png_path) : path(base + ".XXXXXX") {
    const int fd = ::mkstemp(path.data());
    if (fd < 0)
      throw std::runtime_error("plot " + png_path + ": cannot create a temporary file beside it: " +
                               std::strerror(errno));
    ::fchmod(fd, 0644);  // mkstemp makes it 0600; the PNG is renamed into place as it is
    ::close(fd);
  }
  ~TempFile() { ::unlink(path.c_str()); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
};

// A picture's script prints kScriptDone as its last command; the session prints kPictureEnd
// after running it (also when an error cut the script short): what gnuplot said between two
// ends is that picture's, and a picture without its "done" failed.
constexpr const char* kScriptDone = "flexloop: picture drawn";
constexpr const char* kPictureEnd = "flexloop: end of picture";

std::string gnuplot_program() {
  const char* env = std::getenv("FLEXLOOP_GNUPLOT");
  return env && *env ? env : "gnuplot";
}

// One `gnuplot -d` process reading commands from a socket that also takes its output: it runs
// one picture's script file after another (`reset session` between them, so each PNG has the
// bytes a process of its own would draw). A socket, not a pipe: a write to a gnuplot that died
// is an error, not SIGPIPE.
class GnuplotSession {
 public:
  explicit GnuplotSession(std::string program) : program_(std::move(program)) {
    int fds[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) {
      failure_ = std::string("socketpair: ") + std::strerror(errno);
      return;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    for (int to : {STDIN_FILENO, STDOUT_FILENO, STDERR_FILENO})
      posix_spawn_file_actions_adddup2(&actions, fds[1], to);
    std::string arg_d = "-d";
    std::vector<char*> argv{program_.data(), arg_d.data(), nullptr};
    const int rc = ::posix_spawnp(&pid_, program_.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(fds[1]);
    fd_ = fds[0];
    if (rc != 0) {
      pid_ = -1;
      failure_ = "cannot run '" + program_ +
                 "' (is gnuplot installed? apt-get install gnuplot-nox): " + std::strerror(rc);
    }
  }
  ~GnuplotSession() { end(); }
  GnuplotSession(const GnuplotSession&) = delete;
  GnuplotSession& operator=(const GnuplotSession&) = delete;

  /// Empty while gnuplot runs; else why it does not.
  const std::string& failure() const { return failure_; }

  /// Runs a script file; what gnuplot said while it ran, and whether it ran to its end. An error
  /// cuts the script short, maybe inside a multiplot, which is ended before the next picture.
  struct Said {
    bool done = false;
    std::string text;
  };
  Said run(const std::string& script_path) {
    const std::string commands = "load " + quote(script_path) +
                                 "\nunset multiplot\nunset output\nprint " + quote(kPictureEnd) +
                                 "\nreset session\n";
    if (!failure_.empty() || !send_all(commands)) return {false, ended()};
    const std::string end_mark = std::string(kPictureEnd) + "\n";
    std::size_t at;
    while ((at = output_.find(end_mark)) == std::string::npos)
      if (!read_more()) return {false, std::exchange(output_, "") + ended()};
    Said said{false, output_.substr(0, at)};
    output_.erase(0, at + end_mark.size());
    const std::string done_mark = std::string(kScriptDone) + "\n";
    if (const std::size_t d = said.text.find(done_mark); d != std::string::npos)
      said.done = true, said.text.erase(d, done_mark.size());
    return said;
  }

 private:
  bool send_all(const std::string& text) {
    for (std::size_t sent = 0; sent < text.size();) {
      const ssize_t n = ::send(fd_, text.data() + sent, text.size() - sent, MSG_NOSIGNAL);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      sent += static_cast<std::size_t>(n);
    }
    return true;
  }
  bool read_more() {
    char buffer[4096];
    ssize_t n;
    while ((n = ::read(fd_, buffer, sizeof buffer)) < 0 && errno == EINTR) {
    }
    if (n <= 0) return false;
    output_.append(buffer, static_cast<std::size_t>(n));
    return true;
  }
  // Closes the socket (gnuplot reads its end and exits) and reaps it; why it failed, if it did.
  std::string end() {
    if (fd_ >= 0) ::close(fd_), fd_ = -1;
    if (pid_ > 0) {
      int status = 0;
      while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
      }
      pid_ = -1;
      // glibc's posix_spawnp reports a missing program through rc; 127 covers other libcs.
      if (!WIFEXITED(status))
        failure_ = "'" + program_ + "' was killed by signal " + std::to_string(WTERMSIG(status));
      else if (WEXITSTATUS(status) != 0)
        failure_ = "'" + program_ + "' exited with status " + std::to_string(WEXITSTATUS(status));
    }
    return failure_;
  }
  // The process is gone (or never ran): why, as the end of what it said.
  std::string ended() {
    end();
    return failure_.empty() ? "'" + program_ + "' ended" : failure_;
  }

  std::string program_, failure_, output_;
  int fd_ = -1;
  pid_t pid_ = -1;
};

bool is_png_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  static const char kPng[8] = {'\x89', 'P', 'N', 'G', '\r', '\n', '\x1a', '\n'};
  return in && std::memcmp(sig, kPng, 8) == 0;
}

// One picture drawn by the session: its script beside the PNG, gnuplot run on it, the image
// checked and renamed over the PNG. gnuplot's warnings are passed on.
void draw_in(GnuplotSession& session, const PlotScript& p) {
  TempFile image(p.png_path + ".tmp", p.png_path);
  TempFile script(p.png_path + ".gp", p.png_path);
  {
    std::ofstream out(script.path, std::ios::trunc);
    out << preamble(p.spec, image.path) << p.body << "unset output\nprint " << quote(kScriptDone)
        << "\n";
    out.close();
    if (!out) throw std::runtime_error("plot " + p.png_path + ": cannot write gnuplot script");
  }
  const GnuplotSession::Said said = session.run(script.path);
  if (!said.done)
    throw std::runtime_error("plot " + p.png_path + ": " +
                             (session.failure().empty() ? "gnuplot failed: " : "") +
                             tail(said.text));
  if (!is_png_file(image.path))
    throw std::runtime_error("plot " + p.png_path +
                             ": gnuplot produced no PNG: " + tail(said.text));
  if (std::rename(image.path.c_str(), p.png_path.c_str()) != 0)
    throw std::runtime_error("plot " + p.png_path + ": rename: " + std::strerror(errno));
  // gnuplot succeeded but said something (a warning: an empty range, a bad tic): pass it on, a
  // picture drawn around a warning is rarely the one meant (tests/cli/pictures.sh expects none).
  if (!said.text.empty())
    std::fprintf(stderr, "warning: plot %s: gnuplot: %s%s", p.png_path.c_str(), said.text.c_str(),
                 said.text.back() == '\n' ? "" : "\n");
}

void draw_one(const PlotScript& p) {
  GnuplotSession session(gnuplot_program());
  draw_in(session, p);
}

std::string plot_title(const std::string& t) {
  return t.empty() ? "notitle" : "title " + quote(t);
}

std::vector<double> magnitude_db(const std::vector<std::complex<double>>& g) {
  std::vector<double> db(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) db[i] = 20.0 * std::log10(std::abs(g[i]));
  return db;
}

// Datablocks (named $<prefix><k>) and the plot command of a set of lines; `unset key` first when
// none has a title.
std::string lines_body(const PlotSpec& spec, const std::vector<Series>& series,
                       const std::string& prefix, const std::string& png_path) {
  if (series.empty()) throw std::invalid_argument("plot " + png_path + ": no series to draw");
  std::string data, cmd = "plot ";
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    if (s.x.size() != s.y.size())
      throw std::invalid_argument("plot " + png_path + ": series '" + s.title + "' has " +
                                  std::to_string(s.x.size()) + " x and " +
                                  std::to_string(s.y.size()) + " y values");
    const std::string name = "$" + prefix + std::to_string(k);
    data += datablock(name, s.x, {s.y}, spec.logx, spec.logy);
    cmd += (k ? ", \\\n     " : "") + name + " using 1:2 with " +
           checked_style(s.style, "lines lw 2", png_path) + " " + plot_title(s.title);
  }
  const bool untitled =
      std::all_of(series.begin(), series.end(), [](const Series& x) { return x.title.empty(); });
  return data + (untitled ? "unset key\n" : "set key\n") + cmd + "\n";
}

}  // namespace

std::vector<bool> draw_plots(const std::vector<PlotBuilder>& builders, int processes) {
  std::vector<char> drawn(builders.size(), 0);
  std::vector<std::exception_ptr> errors(builders.size());
  std::atomic<std::size_t> next{0};
  const std::string program = gnuplot_program();
  // Each thread its gnuplot, taking the next picture when its last is drawn: the cores stay busy
  // whatever each picture costs, and at most one script per thread is in memory at once.
  const auto worker = [&] {
    std::unique_ptr<GnuplotSession> session;
    for (std::size_t k = next++; k < builders.size(); k = next++) try {
        const std::optional<PlotScript> script = builders[k]();
        if (!script) continue;  // nothing to draw
        if (!session || !session->failure().empty())
          session = std::make_unique<GnuplotSession>(program);
        draw_in(*session, *script);
        drawn[k] = 1;
      } catch (...) {
        errors[k] = std::current_exception();
      }
  };
  const std::size_t width = std::min<std::size_t>(static_cast<std::size_t>(std::max(processes, 1)),
                                                  std::max<std::size_t>(builders.size(), 1));
  std::vector<std::thread> threads;
  for (std::size_t t = 1; t < width; ++t) threads.emplace_back(worker);
  worker();
  for (auto& t : threads) t.join();
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
  return {drawn.begin(), drawn.end()};
}

PlotScript lines_script(const PlotSpec& spec, const std::vector<Series>& series,
                        const std::string& png_path) {
  return {png_path, spec, labels(spec) + lines_body(spec, series, "s", png_path)};
}

void plot_lines(const PlotSpec& spec, const std::vector<Series>& series,
                const std::string& png_path) {
  draw_one(lines_script(spec, series, png_path));
}

void plot_stacked(const PlotSpec& spec, const std::vector<Panel>& panels,
                  const std::string& png_path) {
  draw_one(stacked_script(spec, panels, png_path));
}

PlotScript stacked_script(const PlotSpec& spec, const std::vector<Panel>& panels,
                          const std::string& png_path) {
  if (panels.empty()) throw std::invalid_argument("plot " + png_path + ": no panel to draw");
  PlotSpec s = spec;
  s.title.clear();
  std::string body = "set multiplot layout " + std::to_string(panels.size()) + ",1 title " +
                     quote(spec.title) + "\n";
  for (std::size_t k = 0; k < panels.size(); ++k) {
    s.ylabel = panels[k].ylabel;
    s.xlabel = k + 1 == panels.size() ? spec.xlabel : "";  // one x label, under the last panel
    body += labels(s) + lines_body(s, panels[k].series, "p" + std::to_string(k) + "_", png_path);
  }
  return {png_path, spec, body + "unset multiplot\n"};
}

std::vector<std::complex<double>> channel(const std::vector<Eigen::MatrixXcd>& G,
                                          Eigen::Index output, Eigen::Index input) {
  std::vector<std::complex<double>> c;
  c.reserve(G.size());
  for (const auto& g : G) {
    if (output < 0 || input < 0 || output >= g.rows() || input >= g.cols())
      throw std::invalid_argument(
          "channel (" + std::to_string(output) + ", " + std::to_string(input) + ") outside a " +
          std::to_string(g.rows()) + "x" + std::to_string(g.cols()) + " response");
    c.push_back(g(output, input));
  }
  return c;
}

void plot_bode(const PlotSpec& spec, const std::vector<BodeSeries>& series,
               const std::string& png_path) {
  if (series.empty()) throw std::invalid_argument("plot " + png_path + ": no channel to draw");
  PlotSpec s = spec;
  s.logx = true;
  s.logy = false;
  if (spec.height_px == PlotSpec{}.height_px) s.height_px = 900;  // two panels
  std::string data, mag = "plot ", phase = "plot ";
  for (std::size_t k = 0; k < series.size(); ++k) {
    const BodeSeries& b = series[k];
    if (b.f_hz.size() != b.response.size())
      throw std::invalid_argument("plot " + png_path + ": channel '" + b.title + "' has " +
                                  std::to_string(b.f_hz.size()) + " frequencies and " +
                                  std::to_string(b.response.size()) + " values");
    const std::string name = "$b" + std::to_string(k);
    data += datablock(name, b.f_hz,
                      {magnitude_db(b.response), plant::lti::unwrapped_phase_deg(b.response)}, true,
                      false);
    const std::string style = checked_style(b.style, "lines lw 2", png_path);
    const std::string colour = has_colour(style) ? "" : " lc " + std::to_string(k + 1);
    const std::string sep = k ? ", \\\n     " : "";
    mag += sep + name + " using 1:2 with " + style + colour + " " + plot_title(b.title);
    phase += sep + name + " using 1:3 with " + style + colour + " notitle";
  }
  std::ostringstream body;
  body << data << "set logscale x\n"
       << "set multiplot layout 2,1 title " << quote(spec.title) << "\n"
       << "set xlabel " << quote(or_default(spec.xlabel, "frequency [Hz]")) << "\n"
       << "set ylabel " << quote(or_default(spec.ylabel, "magnitude [dB]")) << "\n"
       << mag << "\n"
       << "unset key\nset ylabel 'phase [deg]'\nset ytics 90\nset mytics 2\n"
       << phase << "\n"
       << "unset multiplot\n";
  draw_one({png_path, s, body.str()});
}

void plot_singular_values(const PlotSpec& spec, const std::vector<SigmaSeries>& systems,
                          const std::string& png_path) {
  if (systems.empty()) throw std::invalid_argument("plot " + png_path + ": no system to draw");
  PlotSpec s = spec;
  s.logx = true;
  s.logy = false;  // dB
  s.xlabel = or_default(spec.xlabel, "frequency [Hz]");
  s.ylabel = or_default(spec.ylabel, "singular value [dB]");
  std::string body = labels(s), cmd = "plot ";
  bool first = true;
  for (std::size_t k = 0; k < systems.size(); ++k) {
    const SigmaSeries& sys = systems[k];
    if (static_cast<Eigen::Index>(sys.f_hz.size()) != sys.sigma.rows())
      throw std::invalid_argument("plot " + png_path + ": system '" + sys.title + "' has " +
                                  std::to_string(sys.f_hz.size()) + " frequencies and " +
                                  std::to_string(sys.sigma.rows()) + " rows of singular values");
    std::vector<std::vector<double>> cols;
    for (Eigen::Index j = 0; j < sys.sigma.cols(); ++j) {
      std::vector<double> db(sys.f_hz.size());
      for (std::size_t i = 0; i < db.size(); ++i)
        db[i] = 20.0 * std::log10(sys.sigma(static_cast<Eigen::Index>(i), j));
      cols.push_back(std::move(db));
    }
    const std::string name = "$g" + std::to_string(k);
    body += datablock(name, sys.f_hz, cols, true, false);
    std::string style = checked_style(sys.style, "", png_path);
    if (style.empty()) style = "lines lw 2 dt " + std::to_string(k % 5 + 1);
    if (!has_colour(style)) style += " lc " + std::to_string(k + 1);
    for (Eigen::Index j = 0; j < sys.sigma.cols(); ++j) {
      cmd += (first ? "" : ", \\\n     ") + name + " using 1:" + std::to_string(j + 2) + " with " +
             style + " " + (j == 0 ? plot_title(sys.title) : std::string("notitle"));
      first = false;
    }
  }
  if (first) throw std::invalid_argument("plot " + png_path + ": no singular values to draw");
  draw_one({png_path, s, body + cmd + "\n"});
}

namespace {

// Labelled ticks on a log axis from lo to hi: every decade, and 2 and 5 between them when the axis
// spans less than three decades (a range of 10 to 100 µs then shows 20 and 50, not one "10").
std::string log_ticks(double lo, double hi) {
  if (!(lo > 0.0) || !(hi > lo)) return "";
  if (hi / lo >= 1e3) return "set xtics 10 format '%g'\nset mxtics 10\n";
  std::string ticks;
  for (double decade = std::pow(10.0, std::floor(std::log10(lo))); decade <= hi; decade *= 10.0)
    for (double step : {1.0, 2.0, 5.0})
      if (const double t = step * decade; t >= lo && t <= hi)
        ticks += (ticks.empty() ? "" : ", ") + format_number(t);
  return "set xtics (" + ticks + ") format '%g'\nset mxtics 10\n";
}

}  // namespace

void plot_histogram(const PlotSpec& spec, const std::vector<double>& bin_edges,
                    const std::vector<double>& counts, const std::string& png_path) {
  draw_one(histogram_script(spec, bin_edges, counts, png_path));
}

PlotScript histogram_script(const PlotSpec& spec, const std::vector<double>& bin_edges,
                            const std::vector<double>& counts, const std::string& png_path) {
  if (counts.empty() || bin_edges.size() != counts.size() + 1)
    throw std::invalid_argument("plot " + png_path + ": need counts.size() + 1 bin edges, got " +
                                std::to_string(bin_edges.size()) + " edges for " +
                                std::to_string(counts.size()) + " counts");
  for (std::size_t i = 0; i + 1 < bin_edges.size(); ++i)
    if (!(bin_edges[i] < bin_edges[i + 1]))
      throw std::invalid_argument("plot " + png_path + ": bin edges must increase (edge " +
                                  std::to_string(i) + ")");
  std::vector<double> centre(counts.size()), width(counts.size());
  double min_positive = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < counts.size(); ++i) {
    centre[i] = 0.5 * (bin_edges[i] + bin_edges[i + 1]);  // x +- width/2 are the edges
    width[i] = bin_edges[i + 1] - bin_edges[i];
    if (counts[i] > 0.0) min_positive = std::min(min_positive, counts[i]);
  }
  std::string body = labels(spec);
  // Columns: centre, width, count; only the count goes on the (possibly log) y axis.
  body += "$h << EOD\n";
  for (std::size_t i = 0; i < counts.size(); ++i)
    body += value(centre[i], spec.logx) + ' ' + format_number(width[i]) + ' ' +
            value(counts[i], spec.logy) + '\n';
  body += "EOD\n";
  body += "unset key\nset xrange [" + format_number(bin_edges.front()) + ":" +
          format_number(bin_edges.back()) + "]\n";
  body += "set style fill solid 0.6 border lc rgb '#1f4e79'\nset boxwidth 1 absolute\n";
  if (spec.logx) body += log_ticks(bin_edges.front(), bin_edges.back());
  if (spec.logy) body += "set ytics 10 format '%g'\nset mytics 10\n";
  if (spec.logy && std::isfinite(min_positive))
    body += "set yrange [" + format_number(min_positive / 2.0) + ":*]\n";
  else if (!spec.logy)
    body += "set yrange [0:*]\n";
  body += "plot $h using 1:3:2 with boxes lc rgb '#4a90d9' notitle\n";
  return {png_path, spec, body};
}

namespace {

// A category label as a gnuplot data string: double-quoted, without the characters that would
// end it.
std::string data_label(const std::string& label) {
  std::string q = "\"";
  for (char c : label)
    if (c != '"' && c != '\\' && c != '\n' && c != '\r') q += c;
  return q + "\"";
}

}  // namespace

void plot_interval_bars(const PlotSpec& spec, const std::vector<std::string>& categories,
                        const std::vector<BarSeries>& series, const std::string& png_path) {
  draw_one(interval_bars_script(spec, categories, series, png_path));
}

PlotScript interval_bars_script(const PlotSpec& spec, const std::vector<std::string>& categories,
                                const std::vector<BarSeries>& series, const std::string& png_path) {
  if (categories.empty() || series.empty())
    throw std::invalid_argument("plot " + png_path + ": no bars to draw");
  for (const BarSeries& b : series)
    if (b.value.size() != categories.size() || b.lo.size() != categories.size() ||
        b.hi.size() != categories.size())
      throw std::invalid_argument("plot " + png_path + ": series '" + b.title + "' needs " +
                                  std::to_string(categories.size()) + " values, lo and hi");
  // Columns: label, then value lo hi of each series.
  std::string body = labels(spec) + "$bars << EOD\n";
  for (std::size_t c = 0; c < categories.size(); ++c) {
    body += data_label(categories[c]);
    for (const BarSeries& b : series)
      body += ' ' + value(b.value[c], false) + ' ' + value(b.lo[c], false) + ' ' +
              value(b.hi[c], false);
    body += '\n';
  }
  body += "EOD\n";
  body +=
      "set style data histograms\nset style histogram errorbars gap 2 lw 1.5\n"
      "set style fill solid 0.6 border -1\nset boxwidth 0.9\nset xzeroaxis lt -1\n"
      "set key\nset autoscale xfixmin\nset autoscale xfixmax\nset offsets 0.5, 0.5, 0, 0\n";
  if (categories.size() > 4) body += "set xtics rotate by -30\n";
  std::string cmd = "plot ";
  for (std::size_t k = 0; k < series.size(); ++k) {
    const std::string col = std::to_string(3 * k + 2);
    cmd += (k ? ", \\\n     " : "") + std::string("$bars using ") + col + ":" +
           std::to_string(3 * k + 3) + ":" + std::to_string(3 * k + 4) +
           (k == 0 ? ":xtic(1)" : "") + " " + plot_title(series[k].title);
  }
  return {png_path, spec, body + cmd + "\n"};
}

}  // namespace flexloop::report
