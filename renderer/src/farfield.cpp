// The far-field barb model's table (farfield.h): direction bins, evaluation and
// sampling, the cache file format, and the memory and disk caches in front of the
// gonioreflectometer (farfield_fit.cpp).
#include "plumage/renderer/farfield.h"
#include "plumage/common/image.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <mutex>
#include <set>

#include "plumage/common/atomic_file.h"
#include "plumage/common/constants.h"
#include "plumage/common/error.h"
#include "plumage/common/interrupt.h"
#include "plumage/common/stats.h"
#include "plumage/common/text.h"
#include "fast_atan2.h"

namespace plumage {
namespace {
// Prints "plumage: warning: LINE" unless this run printed that line already.
void warn_once(const std::string& line) {
  static std::mutex mutex;
  static std::set<std::string> said;
  const std::lock_guard<std::mutex> lock(mutex);
  if (said.insert(line).second) std::cerr << "plumage: warning: " << printable(line) << "\n";
}

constexpr char kMagic[] = "plumage-farfield\n";
constexpr std::uint32_t kVersion = 3;

StatCounter g_fits("Farfield/Tables fitted (gonioreflectometer runs)");
StatCounter g_loaded("Farfield/Tables read from the disk cache");
StatCounter g_refused("Farfield/Cache files refused and refitted");

// FNV-1a, 64 bits: the cache file's checksum and the key's file name.
std::uint64_t fnv1a(const char* p, std::size_t n) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (std::size_t i = 0; i < n; ++i) h = (h ^ std::uint8_t(p[i])) * 0x100000001b3ull;
  return h;
}

template <class T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

struct Reader {
  const std::string& s;
  std::size_t at = 0;
  template <class T>
  T get() {
    if (s.size() - at < sizeof(T)) throw Error("truncated");
    T v;
    std::memcpy(&v, s.data() + at, sizeof v);
    at += sizeof v;
    return v;
  }
};

}  // namespace

float FarfieldBins::solid_angle() const { return 4 * kPiF / float(count()); }

int FarfieldBins::bin(const glm::vec3& d) const {
  const float len2 = glm::dot(d, d);
  if (!(len2 > 0) || !std::isfinite(len2)) return -1;
  const float x = std::clamp(d.x / std::sqrt(len2), -1.0f, 1.0f);
  const int iu = std::clamp(int((x + 1) * 0.5f * float(nu)), 0, nu - 1);
  const float phi = std::atan2(d.y, d.z);  // [-pi, pi]
  const int ip = std::clamp(int((phi + kPiF) / (2 * kPiF) * float(nphi)), 0, nphi - 1);
  return iu * nphi + ip;
}

glm::vec3 FarfieldBins::direction(int b, const glm::vec2& u) const {
  const int iu = b / nphi, ip = b % nphi;
  const float x = std::clamp(-1 + 2 * (float(iu) + u.x) / float(nu), -1.0f, 1.0f);
  const float phi = -kPiF + 2 * kPiF * (float(ip) + u.y) / float(nphi);
  const float r = std::sqrt(std::fmax(0.0f, (1 - x) * (1 + x)));
  return {x, r * std::sin(phi), r * std::cos(phi)};
}

int FarfieldBins::antipode(int b) const {
  const int iu = b / nphi, ip = b % nphi;
  return (nu - 1 - iu) * nphi + (ip + nphi / 2) % nphi;
}

namespace {

// FarfieldBins::lerp, its azimuth from std::atan2 or (kFast, for estimates) atan2_approx.
template <bool kFast>
FarfieldBins::Lerp lerp_in(const FarfieldBins& bins, const glm::vec3& d, int* bin) {
  const int nu = bins.nu, nphi = bins.nphi;
  FarfieldBins::Lerp l{{0, 0, 0, 0}, {0, 0, 0, 0}};
  if (bin) *bin = -1;
  const float len2 = glm::dot(d, d);
  if (!(len2 > 0) || !std::isfinite(len2)) return l;
  const float x = std::clamp(d.x / std::sqrt(len2), -1.0f, 1.0f);
  // The same arithmetic as bin(), so the two agree on every direction.
  const float ux = (x + 1) * 0.5f * float(nu);
  const float up = ((kFast ? atan2_approx(d.y, d.z) : std::atan2(d.y, d.z)) + kPiF) / (2 * kPiF) * float(nphi);
  if (bin) *bin = std::clamp(int(ux), 0, nu - 1) * nphi + std::clamp(int(up), 0, nphi - 1);
  const float fx = std::clamp(ux - 0.5f, 0.0f, float(nu - 1));
  const float fp = up - 0.5f;
  const int i0 = std::min(int(fx), nu - 1), i1 = std::min(i0 + 1, nu - 1);
  const float tx = fx - float(i0);
  const float fpf = std::floor(fp);
  const float tp = std::clamp(fp - fpf, 0.0f, 1.0f);
  const int j0 = ((int(fpf) % nphi) + nphi) % nphi, j1 = (j0 + 1) % nphi;
  l.b[0] = i0 * nphi + j0, l.w[0] = (1 - tx) * (1 - tp);
  l.b[1] = i0 * nphi + j1, l.w[1] = (1 - tx) * tp;
  l.b[2] = i1 * nphi + j0, l.w[2] = tx * (1 - tp);
  l.b[3] = i1 * nphi + j1, l.w[3] = tx * tp;
  return l;
}

}  // namespace

FarfieldBins::Lerp FarfieldBins::lerp(const glm::vec3& d, int* bin) const { return lerp_in<false>(*this, d, bin); }

float FarfieldModel::transmittance(const glm::vec3& local) const {
  const FarfieldBins::Lerp l = bins.lerp(local);
  if (!(l.w[0] + l.w[1] + l.w[2] + l.w[3] > 0)) return 1.0f;
  float t = 0;
  for (int k = 0; k < 4; ++k) t += l.w[k] * T[std::size_t(l.b[k])];
  return t;
}

glm::vec3 FarfieldModel::albedo(int I) const {
  const int n = bins.count();
  glm::vec3 a(0);
  for (int O = 0; O < n; ++O) a += F[std::size_t(I) * n + O] * hat_[std::size_t(O)];
  return a;
}

void FarfieldModel::finish() {
  const int n = bins.count();
  // Mean |d.n| over each bin: 16 x 16 midpoints (the bins are equal-area in (x, phi)).
  cbar_.assign(std::size_t(n), 0.0f);
  constexpr int sub = 16;
  for (int b = 0; b < n; ++b) {
    double sum = 0;
    for (int i = 0; i < sub; ++i)
      for (int j = 0; j < sub; ++j) sum += std::fabs(bins.direction(b, {(i + 0.5f) / sub, (j + 0.5f) / sub}).z);
    cbar_[std::size_t(b)] = float(sum / (sub * sub));
  }
  // H_b: each bin's interpolation weight times |d.n|, integrated over the sphere.
  std::vector<double> hat(std::size_t(n), 0.0);
  const double dw = double(bins.solid_angle()) / (sub * sub);
  for (int b = 0; b < n; ++b)
    for (int i = 0; i < sub; ++i)
      for (int j = 0; j < sub; ++j) {
        const glm::vec3 d = bins.direction(b, {(i + 0.5f) / sub, (j + 0.5f) / sub});
        const FarfieldBins::Lerp l = bins.lerp(d);
        for (int k = 0; k < 4; ++k) hat[std::size_t(l.b[k])] += double(l.w[k]) * std::fabs(d.z) * dw;
      }
  hat_.assign(hat.begin(), hat.end());
  if (has_bsdf()) build_cdfs();
}

// Per outgoing bin O, incident bin I is drawn in proportion to the energy it sends
// to O: lum(F[I][O]) Omega cbar_I (f times the cosine, integrated over the bin).
void FarfieldModel::build_cdfs() {
  const int n = bins.count();
  cdf_.assign(std::size_t(n) * (n + 1), 0.0f);
  for (int O = 0; O < n; ++O) {
    float* c = &cdf_[std::size_t(O) * (n + 1)];
    double acc = 0;
    for (int I = 0; I < n; ++I) {
      c[I] = float(acc);
      acc += double(luminance(F[std::size_t(I) * n + O])) * cbar_[std::size_t(I)];
    }
    c[n] = float(acc);
  }
}

FarfieldModel::Outgoing FarfieldModel::outgoing(const glm::vec3& wo) const {
  Outgoing o;
  o.lo = bins.lerp(wo);
  const std::size_t n = std::size_t(bins.count());
  o.keep = 1;
  for (int k = 0; k < 4; ++k) {
    const std::size_t O = std::size_t(o.lo.b[k]);
    o.keep -= o.lo.w[k] * T[O];
    if (o.lo.w[k] > 0 && cdf_[O * (n + 1) + n] > 0) o.row_mass += o.lo.w[k];
  }
  if (!(o.lo.w[0] + o.lo.w[1] + o.lo.w[2] + o.lo.w[3] > 0)) o.keep = 0;  // a bad wo
  return o;
}

glm::vec3 FarfieldModel::f_cos(const Outgoing& o, const glm::vec3& wi, float* pdf) const {
  if (pdf) *pdf = 0;
  int I;
  const FarfieldBins::Lerp li = bins.lerp(wi, &I);
  if (I < 0 || !(o.keep > 0)) return glm::vec3(0);
  const std::size_t n = std::size_t(bins.count());
  glm::vec3 f(0);
  float p = 0;
  for (int k = 0; k < 4; ++k) {
    if (!(o.lo.w[k] > 0)) continue;
    const std::size_t O = std::size_t(o.lo.b[k]);
    // F is symmetric (F[I][O] == F[O][I], by construction and checked when read
    // from the cache): row O holds the four incident bins side by side.
    glm::vec3 fk(0);
    for (int j = 0; j < 4; ++j) fk += li.w[j] * F[O * n + std::size_t(li.b[j])];
    f += o.lo.w[k] * fk;
    // The sampling density: rows chosen by their interpolation weight (black rows
    // left out), a bin of the row by its cdf, uniform within the bin.
    const float* c = &cdf_[O * (n + 1)];
    if (pdf && c[n] > 0) p += o.lo.w[k] * (c[I + 1] - c[I]) / c[n];
  }
  if (pdf && o.row_mass > 0) *pdf = p / (o.row_mass * bins.solid_angle());
  return f * (std::fabs(wi.z) / std::sqrt(glm::dot(wi, wi)) / o.keep);
}

glm::vec3 FarfieldModel::f_cos_estimate(const Outgoing& o, const glm::vec3& wi) const {
  const FarfieldBins::Lerp li = lerp_in<true>(bins, wi, nullptr);
  if (!(o.keep > 0)) return glm::vec3(0);
  const std::size_t n = std::size_t(bins.count());
  glm::vec3 f(0);
  for (int k = 0; k < 4; ++k) {
    if (!(o.lo.w[k] > 0)) continue;
    const glm::vec3* row = &F[std::size_t(o.lo.b[k]) * n];
    f += o.lo.w[k] * (li.w[0] * row[li.b[0]] + li.w[1] * row[li.b[1]] + li.w[2] * row[li.b[2]] + li.w[3] * row[li.b[3]]);
  }
  return f * (std::fabs(wi.z) / std::sqrt(glm::dot(wi, wi)) / o.keep);
}

bool FarfieldModel::sample(const Outgoing& o, const glm::vec3& u, glm::vec3* wi, glm::vec3* weight,
                           float* pdf) const {
  const FarfieldBins::Lerp& lo = o.lo;
  const int n = bins.count();
  if (!(o.row_mass > 0)) return false;
  // u.z picks the row, and what is left of it (rescaled to [0,1)) the bin.
  float v = u.z * o.row_mass;
  int k = -1;
  for (int j = 0; j < 4; ++j) {
    if (!(lo.w[j] > 0 && cdf_[std::size_t(lo.b[j]) * (n + 1) + n] > 0)) continue;
    k = j;
    if (v < lo.w[j]) break;
    v -= lo.w[j];
  }
  if (k < 0) return false;
  v = std::clamp(v / lo.w[k], 0.0f, 1.0f);
  const float* c = &cdf_[std::size_t(lo.b[k]) * (n + 1)];
  const float target = v * c[n];
  // The bin whose cumulative range holds target, skipping empty bins.
  int I = std::clamp(int(std::upper_bound(c, c + n + 1, target) - c) - 1, 0, n - 1);
  while (I > 0 && !(c[I + 1] > c[I])) --I;
  while (I < n - 1 && !(c[I + 1] > c[I])) ++I;
  if (!(c[I + 1] > c[I])) return false;
  *wi = bins.direction(I, {u.x, u.y});
  const glm::vec3 fc = f_cos(o, *wi, pdf);
  if (!(*pdf > 0)) return false;
  *weight = fc / *pdf;
  return true;
}

std::string FarfieldModel::serialize(const std::string& key) const {
  std::string out(kMagic);
  put(out, kVersion);
  put(out, std::uint32_t(key.size()));
  out += key;
  put(out, std::int32_t(bins.nu));
  put(out, std::int32_t(bins.nphi));
  put(out, std::uint8_t(has_bsdf()));
  for (float t : T) put(out, t);
  for (const glm::vec3& f : F) put(out, f);
  const FarfieldReport& r = report;
  for (double v : {r.seconds, r.noise, r.asymmetry, r.albedo_min, r.albedo_max, r.T_min, r.T_max, r.clamped})
    put(out, v);
  put(out, r.paths);
  put(out, r.rays);
  put(out, fnv1a(out.data(), out.size()));
  return out;
}

FarfieldModel FarfieldModel::deserialize(const std::string& bytes, const std::string& key) {
  const std::size_t magic = std::strlen(kMagic);
  if (bytes.compare(0, magic, kMagic) != 0) throw Error("not a far-field table (bad magic)");
  if (bytes.size() < magic + 8) throw Error("truncated");
  const std::size_t body = bytes.size() - sizeof(std::uint64_t);
  std::uint64_t stored;
  std::memcpy(&stored, bytes.data() + body, sizeof stored);
  if (stored != fnv1a(bytes.data(), body)) throw Error("checksum mismatch (damaged or truncated)");
  Reader r{bytes, magic};
  if (r.get<std::uint32_t>() != kVersion) throw Error("written by another version of the far-field model");
  const auto key_len = r.get<std::uint32_t>();
  if (key_len > body - r.at) throw Error("truncated");
  if (bytes.compare(r.at, key_len, key) != 0) throw Error("stale: fitted for other parameters");
  r.at += key_len;
  FarfieldModel m;
  m.bins.nu = r.get<std::int32_t>();
  m.bins.nphi = r.get<std::int32_t>();
  if (m.bins.nu < 1 || m.bins.nphi < 2 || m.bins.nphi % 2 || m.bins.nu > 1024 || m.bins.nphi > 1024)
    throw Error("bad bin counts");
  const bool bsdf = r.get<std::uint8_t>() != 0;
  const std::size_t n = std::size_t(m.bins.count());
  if ((body - r.at) / sizeof(float) < n * (bsdf ? 3 * n + 1 : 1)) throw Error("truncated");
  m.T.resize(n);
  for (float& t : m.T) {
    t = r.get<float>();
    if (!(t >= 0 && t <= 1)) throw Error("transmittance outside [0, 1]");
  }
  if (bsdf) {
    m.F.resize(n * n);
    for (glm::vec3& f : m.F) {
      f = r.get<glm::vec3>();
      if (!(f.x >= 0 && f.y >= 0 && f.z >= 0) || !std::isfinite(f.x + f.y + f.z))
        throw Error("negative or non-finite BSDF value");
    }
    for (std::size_t I = 0; I < n; ++I)
      for (std::size_t O = 0; O < I; ++O)
        if (m.F[I * n + O] != m.F[O * n + I]) throw Error("BSDF table not symmetric");
  }
  FarfieldReport& rep = m.report;
  for (double* v : {&rep.seconds, &rep.noise, &rep.asymmetry, &rep.albedo_min, &rep.albedo_max, &rep.T_min,
                    &rep.T_max, &rep.clamped})
    *v = r.get<double>();
  rep.paths = r.get<std::int64_t>();
  rep.rays = r.get<std::int64_t>();
  if (r.at != body) throw Error("trailing bytes");
  m.finish();
  return m;
}

std::string farfield_key(const FarfieldGeometry& g, const HairParams* m, const FarfieldFitSettings& s) {
  const SubstructureParams& p = g.params;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "farfield v%u; period %.9g; has_barbules %d; ramus_radius %.9g; barbule_radius %.9g; elevation %.9g; "
                "azimuth %.9g; hooked_fraction %.9g; ribbon_width %.9g; bins %dx%d; paths %d; depth %d; seed %u; polylines %d",
                kVersion, double(g.period), p.barbules_per_side > 0 ? 1 : 0, double(p.ramus_radius),
                double(p.barbule_radius), double(p.elevation_deg), double(p.azimuth_deg), double(p.hooked_fraction),
                double(p.ribbon_width), s.bins.nu, s.bins.nphi, s.paths_per_bin, s.max_depth, s.seed, s.polylines ? 1 : 0);
  std::string key(buf);
  if (m) {
    std::snprintf(buf, sizeof buf, "; beta_m %.9g; beta_n %.9g; alpha %.9g; eta %.9g; sigma_a %.9g,%.9g,%.9g",
                  double(m->beta_m), double(m->beta_n), double(m->alpha_deg), double(m->eta), double(m->sigma_a.x),
                  double(m->sigma_a.y), double(m->sigma_a.z));
    key += buf;
    if (has_medulla(*m)) {  // the key of a clear fibre stays as it was, so its cached tables stay valid
      std::snprintf(buf, sizeof buf, "; medulla %.9g; medulla_sigma_s %.9g,%.9g,%.9g; medulla_sigma_a %.9g,%.9g,%.9g",
                    double(m->medulla_ratio), double(m->medulla_sigma_s.x), double(m->medulla_sigma_s.y),
                    double(m->medulla_sigma_s.z), double(m->medulla_sigma_a.x), double(m->medulla_sigma_a.y),
                    double(m->medulla_sigma_a.z));
      key += buf;
    }
  } else {
    key += "; transmittance only";
  }
  return key;
}

FarfieldFitSettings farfield_fit_settings() {
  FarfieldFitSettings s;
  if (const char* v = std::getenv("PLUMAGE_FARFIELD_PATHS"); v && *v) {
    char* end = nullptr;
    const long n = std::strtol(v, &end, 10);
    if (*end != '\0' || n < 2 || n > 10000000)
      throw Error(std::string("PLUMAGE_FARFIELD_PATHS '") + v + "': give the far-field fit's paths per direction bin, 2 to 10000000");
    s.paths_per_bin = int(n);
  }
  return s;
}

std::filesystem::path farfield_cache_dir() {
  if (const char* d = std::getenv("PLUMAGE_FARFIELD_CACHE")) return d;  // set but empty: no disk cache
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return std::filesystem::path(d) / "plumage/farfield";
  if (const char* d = std::getenv("HOME"); d && *d) return std::filesystem::path(d) / ".cache/plumage/farfield";
  return {};
}

namespace {
std::mutex g_memory_mutex;
std::map<std::string, std::shared_ptr<const FarfieldModel>> g_memory;

// `--stats`: the BSDF tables this process uses, summed (time, paths) or at their
// worst (noise, asymmetry, energy clamp) and over their range (albedo, T).
void publish(const FarfieldModel& m) {
  if (!m.has_bsdf()) return;
  static FarfieldReport all;
  static int tables = 0;
  const FarfieldReport& r = m.report;
  if (tables++ == 0) {
    all = r;
  } else {
    all.seconds += r.seconds;
    all.paths += r.paths;
    all.noise = std::max(all.noise, r.noise);
    all.asymmetry = std::max(all.asymmetry, r.asymmetry);
    all.clamped = std::max(all.clamped, r.clamped);
    all.albedo_min = std::min(all.albedo_min, r.albedo_min);
    all.albedo_max = std::max(all.albedo_max, r.albedo_max);
    all.T_min = std::min(all.T_min, r.T_min);
    all.T_max = std::max(all.T_max, r.T_max);
  }
  stats_set_value("Farfield/Fit: BSDF tables in use", tables);
  stats_set_value("Farfield/Fit: wall seconds, BSDF tables fitted here (0 = all from cache)", all.seconds);
  stats_set_value("Farfield/Fit: incident paths, BSDF tables fitted or read", double(all.paths));
  stats_set_value("Farfield/Fit: noise, worst table (relative RMS standard error of F)", all.noise);
  stats_set_value("Farfield/Fit: asymmetry before symmetrising, worst table (relative RMS)", all.asymmetry);
  stats_set_value("Farfield/Fit: albedo min over bins and tables", all.albedo_min);
  stats_set_value("Farfield/Fit: albedo max over bins and tables", all.albedo_max);
  stats_set_value("Farfield/Fit: transmittance min over bins and tables", all.T_min);
  stats_set_value("Farfield/Fit: transmittance max over bins and tables", all.T_max);
  stats_set_value("Farfield/Fit: energy bound scale-down, worst table", all.clamped);
}
}  // namespace

void farfield_forget_memory() {
  const std::lock_guard<std::mutex> lock(g_memory_mutex);
  g_memory.clear();
}

std::shared_ptr<const FarfieldModel> farfield_model(const FarfieldGeometry& g, const HairParams* material,
                                                    const FarfieldFitSettings& s,
                                                    const std::filesystem::path& cache_dir) {
  const std::string key = farfield_key(g, material, s);
  const std::lock_guard<std::mutex> lock(g_memory_mutex);  // one fit at a time; the fit itself is parallel
  if (auto it = g_memory.find(key); it != g_memory.end()) return it->second;

  std::filesystem::path file;
  if (!cache_dir.empty()) {
    char name[40];
    std::snprintf(name, sizeof name, "ff-%016llx.bin", static_cast<unsigned long long>(fnv1a(key.data(), key.size())));
    file = cache_dir / name;
  }
  std::shared_ptr<const FarfieldModel> model;
  std::error_code ec;
  if (!file.empty() && std::filesystem::exists(file, ec)) {
    try {
      auto m = std::make_shared<FarfieldModel>(FarfieldModel::deserialize(read_file(file, FileRole::Cache), key));
      m->report.seconds = 0;
      model = m;
      ++g_loaded;
    } catch (const Error& e) {
      ++g_refused;
      std::cerr << "plumage: warning: far-field cache " << printable(file.string()) << ": " << e.message()
                << "; refitted and written over\n";
    }
  }
  if (!model) {
    ++g_fits;
    auto m = std::make_shared<FarfieldModel>(measure_farfield(g, material, s));
    model = m;
    if (!file.empty()) {
      try {
        std::filesystem::create_directories(cache_dir);
        write_file_atomic(file, m->serialize(key));
      } catch (const Interrupted&) {
        throw;  // a signal stops the run, not only the cache
      } catch (const std::exception& e) {
        // One line for the folder, not one per table: each of a feather's
        // materials would otherwise say the same.
        const auto* fe = dynamic_cast<const std::filesystem::filesystem_error*>(&e);
        const auto* pe = dynamic_cast<const Error*>(&e);
        const std::string why = fe ? fe->code().message() : pe ? pe->message() : std::string(e.what());
        warn_once("far-field cache folder " + cache_dir.string() + " cannot be written (" + why +
                  "): the tables are fitted again on every run; set $PLUMAGE_FARFIELD_CACHE to a writable folder");
      }
    }
  }
  publish(*model);
  g_memory.emplace(key, model);
  return model;
}

}  // namespace plumage
