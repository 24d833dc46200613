// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// PNG plots for reports, drawn by gnuplot (the distribution's gnuplot-nox).
//
// Each picture is a self-contained gnuplot script (data inline as datablocks). The plot_*
// functions draw one at once: the script goes to a temporary file beside the PNG, `gnuplot -d
// SCRIPT` runs it (-d: ignore the user's ~/.gnuplot so pictures are reproducible), and the
// finished image is renamed over png_path; on failure no PNG is left behind. A report of many
// pictures builds their scripts with the *_script functions and draws them with draw_plots: one
// gnuplot process per core, each drawing one picture after another (`reset session` between
// them, so each PNG has the bytes a process of its own would draw), since starting gnuplot costs
// more than drawing a simple picture. Terminal: pngcairo when this gnuplot has it,
// else the libgd png terminal. Text is drawn literally (noenhanced: "sigma_1" is not a subscript).
// The gnuplot program is taken from the environment variable FLEXLOOP_GNUPLOT when set, else
// `gnuplot` on PATH.
//
// Errors: std::invalid_argument for inconsistent input; std::runtime_error naming png_path when
// gnuplot is missing, fails (its stderr is quoted) or produces no PNG.
#include <Eigen/Dense>
#include <complex>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace flexloop::report {

struct PlotSpec {
  std::string title;
  std::string xlabel;  ///< with units, e.g. "frequency [Hz]"; some plots supply a default
  std::string ylabel;  ///< with units
  bool logx = false;
  bool logy = false;
  int width_px = 1000;
  int height_px = 600;
  /// x_max > x_min: the x axis spans exactly [x_min, x_max]; else it ends where the data do.
  double x_min = 0, x_max = 0;
};

/// A picture not drawn yet: its PNG, its size and title (spec) and the gnuplot commands that
/// draw it (without terminal and output, which the drawing sets).
struct PlotScript {
  std::string png_path;
  PlotSpec spec;
  std::string body;
};

/// Builds one picture's script when its turn comes (none: nothing to draw).
using PlotBuilder = std::function<std::optional<PlotScript>()>;

/// Builds and draws every picture, `processes` at once: each of as many threads runs one gnuplot
/// process and takes the next picture when its last is drawn (so at most `processes` scripts are
/// in memory at once). Which were drawn (false: the builder had nothing to draw). Errors as the
/// plot_* functions', the first in `builders` order, thrown after every picture was tried.
std::vector<bool> draw_plots(const std::vector<PlotBuilder>& builders, int processes);

/// One curve. `style` is a gnuplot `with` clause, e.g. "lines lw 2 dt 2" (dashed) or
/// "linespoints pt 7"; empty means "lines lw 2". Only letters, digits, blanks and . # ' " - _ :
/// are accepted (no second plot element, no function call, no shell escape).
struct Series {
  std::string title;
  std::vector<double> x, y;
  std::string style;
};

/// (c) Generic x-y lines (e.g. time series). Non-finite points, and non-positive ones on a log
/// axis, are left out (the line breaks there).
void plot_lines(const PlotSpec& spec, const std::vector<Series>& series,
                const std::string& png_path);
PlotScript lines_script(const PlotSpec& spec, const std::vector<Series>& series,
                        const std::string& png_path);

/// One panel of a stacked plot: its y label (with units) and its lines.
struct Panel {
  std::string ylabel;
  std::vector<Series> series;
};

/// Panels one above the other over the same x axis (spec.xlabel under the last, spec.title over
/// all), each with its own y range: signals of different size or unit side by side (a
/// disturbance, and a performance output with the controller off and on).
void plot_stacked(const PlotSpec& spec, const std::vector<Panel>& panels,
                  const std::string& png_path);
PlotScript stacked_script(const PlotSpec& spec, const std::vector<Panel>& panels,
                          const std::string& png_path);

/// One frequency-response channel for a Bode plot.
struct BodeSeries {
  std::string title;
  std::vector<double> f_hz;
  std::vector<std::complex<double>> response;
  std::string style;  ///< as Series::style
};

/// (a) Bode plot: magnitude 20 log10|G| [dB] (top) and unwrapped phase [deg] (bottom) against
/// log frequency. spec.ylabel labels the magnitude axis (default "magnitude [dB]"), spec.xlabel
/// defaults to "frequency [Hz]"; logx/logy are ignored (x is always logarithmic).
void plot_bode(const PlotSpec& spec, const std::vector<BodeSeries>& series,
               const std::string& png_path);

/// Column (output, input) of a frequency response: G[k](output, input) for each k.
std::vector<std::complex<double>> channel(const std::vector<Eigen::MatrixXcd>& G,
                                          Eigen::Index output, Eigen::Index input);

/// The singular values of one system over frequency (rows of sigma = frequencies, as returned by
/// plant::lti::singular_values).
struct SigmaSeries {
  std::string title;
  std::vector<double> f_hz;
  Eigen::MatrixXd sigma;
  std::string style;  ///< as Series::style; empty: solid for the 1st system, dashed for the 2nd...
};

/// (b) Singular values 20 log10(sigma_i) [dB] against log frequency, all sigma_i of a system in
/// one colour and line style with one legend entry per system. Defaults: xlabel
/// "frequency [Hz]", ylabel "singular value [dB]".
void plot_singular_values(const PlotSpec& spec, const std::vector<SigmaSeries>& systems,
                          const std::string& png_path);

/// (d) Histogram from bin edges (counts.size() + 1 increasing values) and counts, drawn as boxes.
/// With spec.logy, empty bins are left out and the y axis starts below the smallest non-zero
/// count.
void plot_histogram(const PlotSpec& spec, const std::vector<double>& bin_edges,
                    const std::vector<double>& counts, const std::string& png_path);
PlotScript histogram_script(const PlotSpec& spec, const std::vector<double>& bin_edges,
                            const std::vector<double>& counts, const std::string& png_path);

/// One group member of a bar chart: a value per category and its interval (lo <= value <= hi;
/// NaN: no bar there).
struct BarSeries {
  std::string title;
  std::vector<double> value, lo, hi;
};

/// (e) Bars with error bars: for each category (labels on the x axis) one bar per series, side
/// by side, each with its [lo, hi] interval drawn over it (Sobol indices with their intervals).
void plot_interval_bars(const PlotSpec& spec, const std::vector<std::string>& categories,
                        const std::vector<BarSeries>& series, const std::string& png_path);
PlotScript interval_bars_script(const PlotSpec& spec, const std::vector<std::string>& categories,
                                const std::vector<BarSeries>& series, const std::string& png_path);

}  // namespace flexloop::report
