// writer/csv_probe: the time series of one probe as CSV, one row per frame,
// a header with units, in <scene>.<output name>.csv. A probe is where users look in a laboratory test:
//   "at":                 one material point (the one nearest that position
//                         at the start), followed as it moves: the
//                         settlement of a surface, the pore pressure at a depth;
//   "box_min", "box_max": the points whose centre is in the box now,
//                         reduced (volume-weighted mean, sum, integral, min, max);
//   "face":               a face of the grid, integrated: the flow rate of the
//                         Darcy flux through it, or the fines and liquid that
//                         left through it so far (from the mass ledger, exact).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <suffuse/error.hpp>
#include <suffuse/grid_face.hpp>
#include <suffuse/plugin.hpp>
#include <vector>

namespace {

namespace fs = std::filesystem;
using suffuse::FieldKind;

// What a face probe integrates.
const std::vector<std::string> face_fields = {"darcy_flux", "fines_discharged", "liquid_discharged"};

class CsvProbe final : public suffuse::Writer {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.string_list("fields").doc(
        "Point fields to record (a column per component); a face probe takes darcy_flux (the flow rate out "
        "through the face [m^3/s, per metre in 2D]), fines_discharged and liquid_discharged (the mass that left "
        "through the face so far, net of what came in [kg, per metre in 2D], from the mass ledger)");
    s.vector("at").with_unit("m").may_be_absent().doc(
        "A material point: the one nearest this position at the start, followed as it moves");
    s.vector("box_min").with_unit("m").may_be_absent().doc("Lower corner of a box of points (with box_max)");
    s.vector("box_max").with_unit("m").may_be_absent().doc("Upper corner of a box of points");
    s.choice("reduce", {"mean", "sum", "integral", "min", "max"}).fallback(std::string("mean")).doc(
        "Over a box: mean (volume-weighted), sum (e.g. of a mass), integral (sum of value x volume), min or max");
    s.choice("face", suffuse::grid_face_names()).may_be_absent().doc("A face of the grid, integrated over");
    return s;
  }

  static std::vector<suffuse::ParameterIssue> check(const suffuse::Parameters& p, int dim) {
    std::vector<suffuse::ParameterIssue> issues;
    const int kinds = p.has("at") + (p.has("box_min") || p.has("box_max")) + p.has("face");
    if (kinds != 1)
      issues.push_back({"", "no unique probe", "one of \"at\", \"box_min\" and \"box_max\", or \"face\"",
                        kinds == 0 ? "none" : "several"});
    else if ((p.has("box_min") || p.has("box_max")) && !(p.has("box_min") && p.has("box_max")))
      issues.push_back({p.has("box_min") ? "box_max" : "box_min", "missing box corner", "both box_min and box_max",
                        "only one"});
    if (p.has("face")) {
      if (auto issue = suffuse::grid_face_issue("face", p.string("face"), dim)) issues.push_back(*issue);
      for (const std::string& f : p.string_list("fields"))
        if (std::find(face_fields.begin(), face_fields.end(), f) == face_fields.end())
          issues.push_back({"fields", "not a quantity of a face", "darcy_flux, fines_discharged or liquid_discharged",
                            "\"" + f + "\""});
    }
    if (p.string_list("fields").empty()) issues.push_back({"fields", "no field", "at least one field", "[]"});
    return issues;
  }

  // Point fields must exist in the scene's run (checked at validation).
  static std::vector<std::string> required_fields(const suffuse::Parameters& p, int) {
    if (p.has("face")) {
      for (const std::string& f : p.string_list("fields"))
        if (f == "darcy_flux") return {"darcy_flux"};
      return {"fines_content"};  // the ledger's quantities: a run that tracks fines
    }
    return p.string_list("fields");
  }

  explicit CsvProbe(const suffuse::PluginArgs& args)
      : dim_(args.dim), where_(args.instance), fields_(args.params.string_list("fields")),
        reduce_(args.params.string("reduce")) {
    const auto& p = args.params;
    if (p.has("at")) at_ = p.vector("at");
    if (p.has("box_min")) {
      box_min_ = p.vector("box_min");
      box_max_ = p.vector("box_max");
    }
    if (p.has("face")) face_ = suffuse::grid_face(p.string("face"));
  }

  bool wants_grid_fields() const override {
    return face_ && std::find(fields_.begin(), fields_.end(), "darcy_flux") != fields_.end();
  }
  int default_frame_count() const override { return 200; }

  void open(const fs::path& directory, const std::string& basename) override {
    file_ = directory / (basename + ".csv");
    out_.open(file_, std::ios::trunc);
    if (!out_) throw suffuse::Error("writer/csv_probe: cannot write " + file_.string());
    header_due_ = true;
  }
  void resume(const fs::path& directory, const std::string& basename, const suffuse::ResumePoint& at) override {
    // The point followed when the checkpoint was written (its number in the
    // checkpoint's order, which the restarted run's points keep): picked
    // again from position - displacement, round-off could choose another
    // point of a tie.
    if (!at.state.empty()) {
      try {
        followed_ = std::stoull(at.state);
      } catch (const std::exception&) {
        throw suffuse::Error(where_ + " (writer/csv_probe): the checkpoint's followed point is not a number: " + at.state);
      }
    }
    file_ = directory / (basename + ".csv");
    const bool kept = suffuse::keep_csv_rows_until(file_, at.time);
    out_.open(file_, kept ? std::ios::app : std::ios::trunc);
    if (!out_) throw suffuse::Error("writer/csv_probe: cannot write " + file_.string());
    header_due_ = !kept;
  }

  void write(const suffuse::OutputFrame& frame) override {
    if (header_due_) write_header(frame);
    header_due_ = false;
    out_.precision(17);
    out_ << frame.time;
    for (double v : face_ ? face_values(frame) : point_values(frame)) out_ << ',' << v;
    out_ << '\n';
    out_.flush();  // every row complete on disk: a run that fails later keeps them
  }

 private:
  static const char* component(FieldKind kind, int c) {
    static const char* axes[3] = {"x", "y", "z"};
    static const char* voigt[6] = {"xx", "yy", "zz", "yz", "xz", "xy"};
    static const char* tensor[9] = {"xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"};
    return kind == FieldKind::Vector ? axes[c] : kind == FieldKind::SymmetricTensor ? voigt[c] : tensor[c];
  }

  void write_header(const suffuse::OutputFrame& frame) {
    out_ << "time [s]";
    if (face_) {
      for (const std::string& f : fields_)
        out_ << ',' << (f == "darcy_flux" ? "flow_rate" : f) << " ["
             << (f == "darcy_flux" ? (dim_ == 2 ? "m^2/s" : "m^3/s") : (dim_ == 2 ? "kg/m" : "kg")) << ']';
      out_ << '\n';
      return;
    }
    const suffuse::PointSet& pts = frame.points;
    for (const std::string& f : fields_) {
      const suffuse::FieldId id = pts.id(f);
      const suffuse::FieldInfo& info = pts.info(id);
      std::string unit = info.unit;
      if (box_min_.size() && reduce_ == "integral") unit += " m^" + std::to_string(dim_);
      for (int c = 0; c < pts.components(id); ++c)
        out_ << ',' << f << (pts.components(id) > 1 ? std::string("_") + component(info.kind, c) : "") << " [" << unit
             << ']';
    }
    out_ << '\n';
  }

  std::string saved_state() const override { return followed_ ? std::to_string(*followed_) : std::string(); }

  void points_renumbered(std::span<const std::size_t> new_number) override {
    if (followed_ && *followed_ < new_number.size()) followed_ = new_number[*followed_];
  }

  // The followed point: nearest to `at` in the initial configuration
  // (position - displacement), so a restarted run follows the same one.
  std::size_t followed_point(const suffuse::PointSet& pts) {
    if (followed_) {
      if (*followed_ >= pts.size())
        throw suffuse::Error(where_ + " (writer/csv_probe): the checkpoint's followed point " +
                             std::to_string(*followed_) + " is not among the run's " + std::to_string(pts.size()));
      return *followed_;
    }
    const double* x = pts.data(pts.core().position);
    const double* u = pts.data(pts.core().displacement);
    // Of points equally near, the first in the run's initial numbering
    // (field "id" once the points may have been sorted again).
    const std::optional<suffuse::FieldId> id_field = pts.find("id");
    const double* id = id_field ? pts.data(*id_field) : nullptr;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t p = 0; p < pts.size(); ++p) {
      double d2 = 0;
      for (int a = 0; a < dim_; ++a) d2 += std::pow(x[p * dim_ + a] - u[p * dim_ + a] - at_[a], 2);
      if (d2 < best || (d2 == best && id && id[p] < id[*followed_])) {
        best = d2;
        followed_ = p;
      }
    }
    if (!followed_) throw suffuse::Error(where_ + " (writer/csv_probe): the run has no material points");
    return *followed_;
  }

  std::vector<double> point_values(const suffuse::OutputFrame& frame) {
    const suffuse::PointSet& pts = frame.points;
    std::vector<double> row;
    if (!at_.empty()) {
      const std::size_t p = followed_point(pts);
      for (const std::string& f : fields_) {
        const suffuse::FieldId id = pts.id(f);
        const int k = pts.components(id);
        for (int c = 0; c < k; ++c) row.push_back(pts.data(id)[p * k + c]);
      }
      return row;
    }
    // A box: the points whose centre lies in it now.
    const double* x = pts.data(pts.core().position);
    const double* V = pts.data(pts.core().volume);
    for (const std::string& f : fields_) {
      const suffuse::FieldId id = pts.id(f);
      const int k = pts.components(id);
      const double* v = pts.data(id);
      for (int c = 0; c < k; ++c) {
        double sum = 0, volume = 0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
        std::size_t count = 0;
        for (std::size_t p = 0; p < pts.size(); ++p) {
          bool inside = true;
          for (int a = 0; a < dim_; ++a) inside = inside && x[p * dim_ + a] >= box_min_[a] && x[p * dim_ + a] <= box_max_[a];
          if (!inside) continue;
          const double value = v[p * k + c];
          sum += reduce_ == "sum" ? value : value * V[p];
          volume += V[p];
          lo = std::min(lo, value);
          hi = std::max(hi, value);
          ++count;
        }
        const double nan = std::numeric_limits<double>::quiet_NaN();  // an empty box has no value
        row.push_back(count == 0 && reduce_ != "sum" && reduce_ != "integral" ? nan
                      : reduce_ == "mean"                                     ? sum / volume
                      : reduce_ == "min"                                      ? lo
                      : reduce_ == "max"                                      ? hi
                                                                              : sum);
      }
    }
    return row;
  }

  std::vector<double> face_values(const suffuse::OutputFrame& frame) {
    std::vector<double> row;
    const std::string face_name = suffuse::grid_face_names()[face_->axis * 2 + (face_->upper ? 1 : 0)];
    for (const std::string& f : fields_) {
      if (f == "darcy_flux") {
        // Q = sum over the face's nodes of q . n A (outward positive).
        const auto flux = std::find_if(frame.grid_fields.begin(), frame.grid_fields.end(),
                                       [](const suffuse::GridField& g) { return g.name == "darcy_flux"; });
        if (flux == frame.grid_fields.end())
          throw suffuse::Error(where_ + " (writer/csv_probe): the run projects no Darcy flux (a dry run?)");
        double q = 0;
        for (std::int64_t node : suffuse::face_nodes(frame.grid, *face_))
          q += flux->values[node * dim_ + face_->axis] * face_->outward() *
               suffuse::face_node_area(frame.grid, *face_, node);
        row.push_back(q);
        continue;
      }
      double net = 0;  // no opening on that face: nothing crossed it
      bool found = false;  // every account on the face (its parts, each named)
      if (frame.ledger)
        for (const suffuse::BoundaryDischarge& d : frame.ledger->boundaries)
          if (d.grid_face == face_name) {
            const double crossed = f == "fines_discharged" ? d.fines_out - d.fines_in : d.liquid_out - d.liquid_in;
            net = found ? net + crossed : crossed;
            found = true;
          }
      row.push_back(net);
    }
    return row;
  }

  int dim_;
  std::string where_;
  std::vector<std::string> fields_;
  std::string reduce_;
  std::vector<double> at_, box_min_, box_max_;
  std::optional<suffuse::GridFace> face_;
  std::optional<std::size_t> followed_;
  fs::path file_;
  std::ofstream out_;
  bool header_due_ = true;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::Writer, CsvProbe>(
      "writer/csv_probe",
      "Time series of a probe as CSV with units: a field at a material point, reduced over a box, or integrated "
      "over a face of the grid (flow rate, fines and liquid discharged)");
}
