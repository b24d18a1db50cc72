// Checkpoints: everything a step needs, so that a restarted run continues
// exactly (bit for bit) as the run that wrote it would have.
//
// A restarted run is first built from the scene as a new run is (every
// plugin's set-up sees the same initial state), then the checkpoint replaces
// what evolves: every point field (plugins keep their evolving state in
// point fields), the ledger's boundary totals, the reactions' sums, the
// quasi-static solver's last equilibrium (its nodal pressures), the clock,
// and how many frames each writer wrote.
//
// File: a text line "suffuse checkpoint 1", a one-line JSON header, the
// values (little-endian doubles) in the header's order, then an FNV-1a hash
// of everything before it. Written to a temporary name, then renamed.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "mpm/domain.hpp"
#include "common/fnv1a.hpp"
#include "mpm/point_order.hpp"
#include "mpm/reactions.hpp"
#include "transport/species_transport.hpp"
#include "suffuse/error.hpp"
#include "suffuse/simulation.hpp"
#include "suffuse/version.hpp"

namespace suffuse {

using detail::fnv1a;

namespace {

constexpr const char* magic = "suffuse checkpoint 1";

// Writes the file piece by piece, hashing as it goes: no copy of the point
// fields in memory (a copy tripled the peak memory of large runs at their end).
class HashedFile {
 public:
  explicit HashedFile(const std::filesystem::path& file) : out_(file, std::ios::binary) {}
  void put(std::string_view bytes) {
    out_.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    hash_ = detail::fnv1a(bytes, hash_);
  }
  void put(const double* v, std::size_t n) { put({reinterpret_cast<const char*>(v), n * sizeof(double)}); }
  // The hash of everything put, then the stream's state.
  bool finish() {
    out_.write(reinterpret_cast<const char*>(&hash_), sizeof hash_);
    out_.close();
    return !out_.fail();
  }

 private:
  std::ofstream out_;
  std::uint64_t hash_ = detail::fnv1a_basis;
};

}  // namespace

void Simulation::save_checkpoint(const std::filesystem::path& file, const WriterCheckpoint& writers,
                                 std::optional<double> ends_run_at) const {
  // Every process's points, in the serial run's order: the same file as a
  // serial run's (the first process writes it).
  const PointSet& pts = domain_->gathered_points();
  if (!domain_->comm.root()) return;
  const SimulationClock::State clock = clock_.state();
  nlohmann::ordered_json h;
  h["suffuse_version"] = framework_version;
  h["scene"] = scene_.file.string();
  h["scene_fingerprint"] = scene_.fingerprint;
  h["dimension"] = scene_.dim;
  h["points"] = pts.size();
  h["time"] = clock.time;
  h["steps"] = clock.steps;
  h["dt"] = clock.nominal;
  h["clock_origin"] = clock.origin;
  h["steps_since_origin"] = clock.since_origin;
  h["point_order_reference"] = point_order_->reference();  // when the points are sorted next
  h["writer_frames"] = writers.frames;
  h["writer_states"] = writers.states;
  h["outputs_written_at_its_step"] = writers.written_at_its_step;
  if (ends_run_at) h["ends_run_at"] = *ends_run_at;
  if (collapse_from_) {  // a collapse's state: a restart goes on with it
    h["collapse_from"] = *collapse_from_;
    h["failure_time"] = failure_->time;
    h["failure_reason"] = failure_->reason;
  }
  for (FieldId f = 0; f < pts.field_count(); ++f)
    h["fields"].push_back({{"name", pts.info(f).name}, {"components", pts.components(f)}});
  const std::vector<double> ledger = species_ ? species_->saved_state() : std::vector<double>{};
  const std::vector<double> reactions = reactions_->saved_state();
  h["ledger_values"] = ledger.size();
  h["reaction_values"] = reactions.size();
  const std::vector<double> solver = solver_state();
  h["solver_values"] = solver.size();

  const std::string header = std::string(magic) + "\n" + h.dump() + "\n";  // before any file is made

  const std::filesystem::path tmp = file.string() + ".part";
  // A scene with nothing else to write has not made its output directory.
  std::error_code ignored;
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), ignored);
  HashedFile out(tmp);
  out.put(header);
  for (FieldId f = 0; f < pts.field_count(); ++f) out.put(pts.data(f), pts.values(f).size());
  out.put(ledger.data(), ledger.size());
  out.put(reactions.data(), reactions.size());
  out.put(solver.data(), solver.size());
  if (!out.finish()) throw Error("cannot write the checkpoint " + file.string());
  std::filesystem::rename(tmp, file);  // never a half-written checkpoint under its name
}

Simulation::Restored Simulation::load_checkpoint(const std::filesystem::path& file) {
  const std::string where = "cannot restart from " + file.string() + ": ";
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  if (!in) throw Error(where + "no such file");
  // Read in one piece, one copy of the file in memory; a stream that cannot
  // tell its size (a pipe) is read to its end.
  std::string bytes;
  const std::streamoff size = in.tellg();
  if (size >= 0 && in.seekg(0)) {
    bytes.resize(static_cast<std::size_t>(size));
    in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!in) throw Error(where + "cannot read it");
  } else {
    in.clear();
    std::ostringstream all;
    all << in.rdbuf();
    bytes = all.str();
  }
  const std::size_t first = bytes.find('\n');
  if (first == std::string::npos || bytes.compare(0, first, magic) != 0)
    throw Error(where + "not a suffuse checkpoint (its first line is not \"" + magic + "\")");
  const std::size_t second = bytes.find('\n', first + 1);
  if (second == std::string::npos || bytes.size() < second + 1 + sizeof(std::uint64_t))
    throw Error(where + "the file is truncated");
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + bytes.size() - sizeof stored, sizeof stored);
  if (fnv1a(std::string_view(bytes).substr(0, bytes.size() - sizeof stored)) != stored)
    throw Error(where + "the file is damaged or truncated (its checksum does not match)");
  nlohmann::json h;
  try {
    h = nlohmann::json::parse(bytes.substr(first + 1, second - first - 1));
  } catch (const std::exception& e) {
    throw Error(where + "its header is not valid JSON (" + e.what() + ")");
  }

  // The same scene (only /time/end and /checkpoint may differ) and version.
  const std::string version = h.value("suffuse_version", "");
  if (version != framework_version)
    throw Error(where + "it was written by suffuse " + version + ", this is " + framework_version);
  if (h.value("scene_fingerprint", "") != scene_.fingerprint)
    throw Error(where + "it was written by a run of another scene (" + h.value("scene", "?") +
                "); a restart may change /time/end and /checkpoint only");
  // On many processes each reads the file and keeps its own points.
  PointSet& pts = domain_->points;
  const std::size_t total = domain_->total_points(), mine = domain_->first_point();
  if (h.value("points", std::size_t{0}) != total || h.value("dimension", 0) != scene_.dim)
    throw Error(where + "it holds " + std::to_string(h.value("points", std::size_t{0})) + " points, the scene " +
                std::to_string(total));

  const char* v = bytes.data() + second + 1;
  const char* end = bytes.data() + bytes.size() - sizeof stored;
  auto take = [&](double* out, std::size_t n, const std::string& what) {
    if (static_cast<std::size_t>(end - v) < n * sizeof(double)) throw Error(where + "too few values for " + what);
    // An empty field (a dry run's ledger) has no storage: memcpy from or to
    // a null pointer is undefined even for no bytes (found by UBSan).
    if (n > 0) std::memcpy(out, v, n * sizeof(double));
    v += n * sizeof(double);
  };
  auto skip = [&](std::size_t n, const std::string& what) {
    if (static_cast<std::size_t>(end - v) < n * sizeof(double)) throw Error(where + "too few values for " + what);
    v += n * sizeof(double);
  };
  const auto& fields = h.at("fields");
  if (fields.size() != pts.field_count())
    throw Error(where + "it holds " + std::to_string(fields.size()) + " point fields, this run " +
                std::to_string(pts.field_count()));
  for (const auto& f : fields) {
    const std::string name = f.at("name").get<std::string>();
    const auto id = pts.find(name);
    if (!id || pts.components(*id) != f.at("components").get<int>())
      throw Error(where + "point field '" + name + "' is not in this run (or has another number of components)");
    const auto m = static_cast<std::size_t>(pts.components(*id));
    const std::string what = "point field '" + name + "'";
    skip(mine * m, what);
    take(pts.data(*id), pts.values(*id).size(), what);
    skip((total - mine - pts.size()) * m, what);
  }
  std::vector<double> ledger(h.at("ledger_values").get<std::size_t>());
  std::vector<double> reactions(h.at("reaction_values").get<std::size_t>());
  take(ledger.data(), ledger.size(), "the ledger");
  take(reactions.data(), reactions.size(), "the reactions");
  std::vector<double> solver(h.at("solver_values").get<std::size_t>());
  take(solver.data(), solver.size(), "the quasi-static solver's state");
  if (v != end) throw Error(where + "it holds more values than its header lists");
  if (species_) species_->restore_state(ledger);
  else if (!ledger.empty()) throw Error(where + "it holds a ledger, this run is dry");
  reactions_->restore_state(reactions);
  restore_solver_state(std::move(solver));
  point_order_->restore_reference(h.at("point_order_reference").get<double>());
  renumber_loaded_points();  // the checkpoint's points may have been sorted
  clock_.restore({h.at("dt").get<double>(), h.at("time").get<double>(), h.at("clock_origin").get<double>(),
                  h.at("steps").get<std::size_t>(), h.at("steps_since_origin").get<std::size_t>()});
  Restored restored{{h.at("writer_frames").get<std::vector<std::size_t>>(),
                     h.at("writer_states").get<std::vector<std::string>>()},
                    std::nullopt};
  if (h.contains("ends_run_at")) restored.ends_run_at = h.at("ends_run_at").get<double>();
  restored.writers.written_at_its_step = h.value("outputs_written_at_its_step", false);
  if (h.contains("collapse_from")) {
    if (!scene_.failure || !scene_.failure->collapse) {
      std::ostringstream at;
      at << h.at("failure_time").get<double>();
      throw Error(where + "it holds the collapse after a failure at t = " + at.str() +
                  " s, and the scene has no /failure/collapse to go on with");
    }
    collapse_from_ = h.at("collapse_from").get<double>();
    failure_ = RunFailure{h.at("failure_time").get<double>(), h.at("failure_reason").get<std::string>()};
  }
  return restored;
}

}  // namespace suffuse
