#include "offline/report/plot.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
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
#include <sstream>
#include <stdexcept>
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

// A whole (small) file: gnuplot's log.
std::string slurp_whole(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
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

// What each picture's commands print when its PNG is written: the log's text between two of
// them is that picture's (a warning goes with the picture it is about).
constexpr const char* kPictureDone = "flexloop: picture drawn";

// One gnuplot process and the pictures it draws, in order: its script, its log (stdout and
// stderr) and a temporary image per picture, each renamed over its PNG once checked.
struct GnuplotRun {
  std::vector<std::size_t> pictures;  // indices into the scripts
  std::unique_ptr<TempFile> script, log;
  std::vector<std::unique_ptr<TempFile>> images;
  pid_t pid = -1;
  std::string spawn_error;  // non-empty: the process did not start
};

std::string gnuplot_program() {
  const char* env = std::getenv("FLEXLOOP_GNUPLOT");
  return env && *env ? env : "gnuplot";
}

// The pictures shared out over at most `processes` runs, largest first to the run with the
// fewest pixels so far (drawing and compressing a PNG costs about its pixels); each run's
// pictures in the scripts' order.
std::vector<std::vector<std::size_t>> share_out(const std::vector<PlotScript>& scripts,
                                                int processes) {
  const auto pixels = [&](std::size_t k) {
    return static_cast<long>(scripts[k].spec.width_px) * scripts[k].spec.height_px;
  };
  std::vector<std::size_t> by_size(scripts.size());
  for (std::size_t k = 0; k < by_size.size(); ++k) by_size[k] = k;
  std::stable_sort(by_size.begin(), by_size.end(),
                   [&](std::size_t a, std::size_t b) { return pixels(a) > pixels(b); });
  const std::size_t width =
      std::min<std::size_t>(static_cast<std::size_t>(std::max(processes, 1)), scripts.size());
  std::vector<std::vector<std::size_t>> shares(width);
  std::vector<long> load(width, 0);
  for (std::size_t k : by_size) {
    const auto least = static_cast<std::size_t>(
        std::distance(load.begin(), std::min_element(load.begin(), load.end())));
    shares[least].push_back(k);
    load[least] += pixels(k);
  }
  for (auto& share : shares) std::sort(share.begin(), share.end());
  return shares;
}

// Writes the run's script: each picture's terminal, output and commands, then its mark, then a
// reset of everything it set (its datablocks too) before the next.
void write_script(GnuplotRun& run, const std::vector<PlotScript>& scripts) {
  const std::string& first = scripts[run.pictures.front()].png_path;
  run.script = std::make_unique<TempFile>(first + ".gp", first);
  run.log = std::make_unique<TempFile>(first + ".log", first);
  std::ofstream out(run.script->path, std::ios::trunc);
  for (std::size_t k : run.pictures) {
    const PlotScript& p = scripts[k];
    run.images.push_back(std::make_unique<TempFile>(p.png_path + ".tmp", p.png_path));
    out << preamble(p.spec, run.images.back()->path) << p.body << "unset output\n"
        << "print " << quote(kPictureDone) << "\nreset session\n";
  }
  out.close();
  if (!out) throw std::runtime_error("plot " + first + ": cannot write gnuplot script");
}

// Starts `gnuplot -d SCRIPT`, its output to the log; pid -1 and spawn_error when it cannot.
void start_gnuplot(GnuplotRun& run, const std::string& program) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, run.log->path.c_str(),
                                   O_WRONLY | O_TRUNC, 0);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  std::string arg_d = "-d";
  std::vector<char*> argv{const_cast<char*>(program.c_str()), arg_d.data(), run.script->path.data(),
                          nullptr};
  const int rc = ::posix_spawnp(&run.pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    run.pid = -1;
    run.spawn_error = "cannot run '" + program +
                      "' (is gnuplot installed? apt-get install gnuplot-nox): " + std::strerror(rc);
  }
}

// The process's end: empty when it exited 0, else why not.
std::string wait_for(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return std::string("waitpid: ") + std::strerror(errno);
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
  // glibc's posix_spawnp reports a missing program through rc; 127 covers other shells/libcs.
  return WIFEXITED(status) ? "exited with status " + std::to_string(WEXITSTATUS(status))
                           : "was killed by signal " + std::to_string(WTERMSIG(status));
}

// The log cut at each picture's mark: element k is what gnuplot said while drawing the run's
// k-th picture; one more element (what it said after the last mark) when it stopped early.
std::vector<std::string> said_per_picture(const std::string& log) {
  const std::string mark = std::string(kPictureDone) + "\n";
  std::vector<std::string> said;
  std::size_t from = 0;
  for (std::size_t at; (at = log.find(mark, from)) != std::string::npos; from = at + mark.size())
    said.push_back(log.substr(from, at - from));
  said.push_back(log.substr(from));
  return said;
}

bool is_png_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  static const char kPng[8] = {'\x89', 'P', 'N', 'G', '\r', '\n', '\x1a', '\n'};
  return in && std::memcmp(sig, kPng, 8) == 0;
}

// After the run's process ended (`ended`: empty, or why it failed): each drawn picture checked
// and moved into place, gnuplot's warnings passed on; the first picture not drawn is the error.
void finish(const GnuplotRun& run, const std::vector<PlotScript>& scripts, const std::string& ended,
            const std::string& program) {
  const auto failed = [&](std::size_t i, const std::string& why) {
    return std::runtime_error("plot " + scripts[run.pictures[i]].png_path + ": " + why);
  };
  if (!run.spawn_error.empty()) throw failed(0, run.spawn_error);
  const std::vector<std::string> said = said_per_picture(slurp_whole(run.log->path));
  for (std::size_t i = 0; i < run.pictures.size(); ++i) {
    const std::string& png_path = scripts[run.pictures[i]].png_path;
    const std::string& image = run.images[i]->path;
    const bool drawn = i + 1 < said.size();  // its mark was printed
    if (!drawn && !ended.empty())
      throw failed(i, "'" + program + "' " + ended + ": " + tail(said[i]));
    if (!drawn || !is_png_file(image)) throw failed(i, "gnuplot produced no PNG: " + tail(said[i]));
    if (std::rename(image.c_str(), png_path.c_str()) != 0)
      throw failed(i, std::string("rename: ") + std::strerror(errno));
    // gnuplot succeeded but said something (a warning: an empty range, a bad tic): pass it on, a
    // picture drawn around a warning is rarely the one meant (tests/cli/pictures.sh expects none).
    if (!said[i].empty())
      std::fprintf(stderr, "warning: plot %s: gnuplot: %s%s", png_path.c_str(), said[i].c_str(),
                   said[i].back() == '\n' ? "" : "\n");
  }
  if (!ended.empty())  // every picture drawn, yet gnuplot failed after the last
    throw failed(run.pictures.size() - 1, "'" + program + "' " + ended + ": " + tail(said.back()));
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

void draw_plots(const std::vector<PlotScript>& scripts, int processes) {
  if (scripts.empty()) return;
  const std::string program = gnuplot_program();
  std::vector<GnuplotRun> runs;
  for (auto& share : share_out(scripts, processes)) {
    runs.emplace_back().pictures = std::move(share);
    write_script(runs.back(), scripts);
  }
  for (GnuplotRun& run : runs) start_gnuplot(run, program);
  std::vector<std::string> ended;
  for (const GnuplotRun& run : runs) ended.push_back(run.pid > 0 ? wait_for(run.pid) : "");
  // Every run's drawn pictures into place before the first error (in the scripts' order) is
  // thrown: the error a single process per picture would have met first.
  std::vector<std::pair<std::size_t, std::exception_ptr>> errors;
  for (std::size_t r = 0; r < runs.size(); ++r) try {
      finish(runs[r], scripts, ended[r], program);
    } catch (...) {
      errors.emplace_back(runs[r].pictures.front(), std::current_exception());
    }
  if (errors.empty()) return;
  std::rethrow_exception(
      std::min_element(errors.begin(), errors.end(), [](const auto& a, const auto& b) {
        return a.first < b.first;
      })->second);
}

PlotScript lines_script(const PlotSpec& spec, const std::vector<Series>& series,
                        const std::string& png_path) {
  return {png_path, spec, labels(spec) + lines_body(spec, series, "s", png_path)};
}

void plot_lines(const PlotSpec& spec, const std::vector<Series>& series,
                const std::string& png_path) {
  draw_plots({lines_script(spec, series, png_path)}, 1);
}

void plot_stacked(const PlotSpec& spec, const std::vector<Panel>& panels,
                  const std::string& png_path) {
  draw_plots({stacked_script(spec, panels, png_path)}, 1);
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
  draw_plots({{png_path, s, body.str()}}, 1);
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
  draw_plots({{png_path, s, body + cmd + "\n"}}, 1);
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
  draw_plots({histogram_script(spec, bin_edges, counts, png_path)}, 1);
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
  draw_plots({interval_bars_script(spec, categories, series, png_path)}, 1);
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
