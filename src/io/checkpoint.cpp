#include "velum/io/checkpoint.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "velum/io/results_writer.hpp"

namespace velum::io {
namespace {

// Version 2 adds the processes, the model's fingerprint and a checksum.
constexpr char kMagic[8] = {'V', 'E', 'L', 'U', 'M', 'C', 'K', '2'};
constexpr char kMagicV1[8] = {'V', 'E', 'L', 'U', 'M', 'C', 'K', '1'};

/// FNV-1a, 64 bits: catches an edited or damaged byte (not an attack: anyone can recompute it).
std::uint64_t checksum(const char* p, size_t n) {
  std::uint64_t h = 14695981039346656037ull;
  for (size_t i = 0; i < n; ++i) {
    h ^= static_cast<unsigned char>(p[i]);
    h *= 1099511628211ull;
  }
  return h;
}

class Out {
 public:
  template <class T>
  void pod(const T& x) {
    buf_.append(reinterpret_cast<const char*>(&x), sizeof x);
  }
  void doubles(const double* x, long n) {
    pod(n);
    buf_.append(reinterpret_cast<const char*>(x), static_cast<size_t>(n) * sizeof(double));
  }
  void vec(const VecX& v) { doubles(v.data(), v.size()); }
  void vec(const std::vector<double>& v) { doubles(v.data(), static_cast<long>(v.size())); }
  void text(const std::string& s) {
    pod(static_cast<long>(s.size()));
    buf_ += s;
  }
  std::string buf_;
};

class In {
 public:
  In(std::string data, std::string name) : data_(std::move(data)), name_(std::move(name)) {}
  template <class T>
  T pod() {
    T x;
    need(sizeof x);
    std::memcpy(&x, data_.data() + at_, sizeof x);
    at_ += sizeof x;
    return x;
  }
  std::vector<double> doubles() {
    const long n = pod<long>();
    if (n < 0) bad();
    need(static_cast<size_t>(n) * sizeof(double));
    std::vector<double> v(static_cast<size_t>(n));
    if (!v.empty())  // an empty vector's data() may be null, which memcpy must never get
      std::memcpy(v.data(), data_.data() + at_, v.size() * sizeof(double));
    at_ += v.size() * sizeof(double);
    return v;
  }
  VecX vec() {
    const std::vector<double> v = doubles();
    return Eigen::Map<const VecX>(v.data(), static_cast<Eigen::Index>(v.size()));
  }
  std::string text() {
    const long n = pod<long>();
    if (n < 0) bad();
    need(static_cast<size_t>(n));
    std::string s = data_.substr(at_, static_cast<size_t>(n));
    at_ += static_cast<size_t>(n);
    return s;
  }
  bool done() const { return at_ == data_.size(); }
  [[noreturn]] void bad() const {
    throw std::runtime_error(name_ + ": not a Velum checkpoint, or cut short");
  }

 private:
  void need(size_t n) const {
    if (data_.size() - at_ < n) bad();
  }
  std::string data_, name_;
  size_t at_ = 0;
};

}  // namespace

void write_checkpoint(const std::filesystem::path& path, const CheckpointFile& c) {
  Out o;
  o.buf_.append(kMagic, sizeof kMagic);
  o.pod(c.dofs);
  o.text(c.model);
  o.pod(c.processes);
  o.text(c.fingerprint);
  const LoopResume& l = c.run.loop;
  o.pod(l.t), o.pod(l.step), o.pod(l.steps), o.pod(l.iterations), o.pod(l.factorizations),
      o.pod(l.cutbacks);
  o.pod(l.control.h), o.pod(l.control.easy), o.pod(l.control.streak),
      o.pod(l.control.streak_needed), o.pod(l.control.trying);
  o.vec(c.run.state.u), o.vec(c.run.state.v), o.vec(c.run.state.a);
  const Energies& e = c.run.energy;
  o.pod(e.kinetic), o.pod(e.strain), o.pod(e.external_work), o.pod(e.damping);
  o.vec(c.run.integrator), o.vec(c.run.analysis);
  o.pod(static_cast<long>(c.run.warnings.size()));
  for (const auto& w : c.run.warnings) o.text(w);
  o.pod(c.history_bytes), o.pod(c.steps_bytes);
  o.vec(c.frame_times);
  o.vec(c.run.loads);
  o.pod(checksum(o.buf_.data(), o.buf_.size()));
  write_file_atomically(path, o.buf_);
}

CheckpointFile read_checkpoint(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto st = fs::status(path, ec);
  if (!fs::exists(st))
    throw std::runtime_error(path.string() +
                             ": no checkpoint (the run needs output.checkpoint to write one)");
  // A device or a FIFO put in its place would be read without end or block.
  if (!fs::is_regular_file(st))
    throw std::runtime_error(path.string() + ": not a regular file, so not a Velum checkpoint");
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error(path.string() + ": cannot open the checkpoint");
  std::string data((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (data.size() >= sizeof kMagic && std::memcmp(data.data(), kMagicV1, sizeof kMagicV1) == 0)
    throw std::runtime_error(path.string() +
                             ": a checkpoint of an older Velum (without a checksum): run the "
                             "model again from its start");
  std::uint64_t sum = 0;
  if (data.size() >= sizeof kMagic + sizeof sum) {
    std::memcpy(&sum, data.data() + data.size() - sizeof sum, sizeof sum);
    data.resize(data.size() - sizeof sum);
    if (std::memcmp(data.data(), kMagic, sizeof kMagic) == 0 &&
        sum != checksum(data.data(), data.size()))
      throw std::runtime_error(path.string() +
                               ": the checkpoint's checksum does not match: it was changed or "
                               "damaged since it was written");
  }
  In in(std::move(data), path.string());
  char magic[sizeof kMagic];
  for (char& ch : magic) ch = in.pod<char>();
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) in.bad();
  CheckpointFile c;
  c.dofs = in.pod<int>();
  c.model = in.text();
  c.processes = in.pod<int>();
  c.fingerprint = in.text();
  LoopResume& l = c.run.loop;
  l.t = in.pod<double>(), l.step = in.pod<double>();
  l.steps = in.pod<int>(), l.iterations = in.pod<int>(), l.factorizations = in.pod<int>();
  l.cutbacks = in.pod<int>();
  l.control.h = in.pod<double>(), l.control.easy = in.pod<int>();
  l.control.streak = in.pod<int>(), l.control.streak_needed = in.pod<int>();
  l.control.trying = in.pod<bool>();
  c.run.state.u = in.vec(), c.run.state.v = in.vec(), c.run.state.a = in.vec();
  Energies& e = c.run.energy;
  e.kinetic = in.pod<double>(), e.strain = in.pod<double>();
  e.external_work = in.pod<double>(), e.damping = in.pod<double>();
  c.run.integrator = in.doubles(), c.run.analysis = in.doubles();
  const long nw = in.pod<long>();
  if (nw < 0 || nw > 1'000'000) in.bad();
  for (long i = 0; i < nw; ++i) c.run.warnings.push_back(in.text());
  c.history_bytes = in.pod<long>(), c.steps_bytes = in.pod<long>();
  c.frame_times = in.doubles();
  c.run.loads = in.doubles();
  if (!in.done()) in.bad();
  // Whole and unchanged; still, nothing below may be read as a time or a size without sense.
  auto finite = [](const VecX& v) { return v.allFinite(); };
  const bool sane = c.dofs >= 0 && c.processes >= 1 && std::isfinite(l.t) &&
                    std::isfinite(l.step) && std::isfinite(l.control.h) && l.control.h >= 0 &&
                    l.steps >= 0 && finite(c.run.state.u) && finite(c.run.state.v) &&
                    finite(c.run.state.a) && c.history_bytes >= 0 && c.steps_bytes >= 0;
  if (!sane)
    throw std::runtime_error(path.string() +
                             ": the checkpoint holds a value no run writes (a time, step or "
                             "state that is not finite, or a negative size)");
  return c;
}

}  // namespace velum::io
