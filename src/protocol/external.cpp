// The process protocol, cullproof's side (see cullproof/protocol/external.hpp and docs/protocol.md).
//
// The child runs with pipes on its stdin and stdout (stderr is inherited, for its own messages).
// POSIX fork/exec and poll() are used directly: the protocol needs a read with a deadline on a
// line-oriented pipe and nothing more. SIGPIPE is ignored for the write, so a program that has
// exited is reported as such instead of killing cullproof.
#include "cullproof/protocol/external.hpp"

#include "cullproof/io/case_io.hpp"
#include "cullproof/io/limits.hpp"
#include "cullproof/protocol/protocol.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

namespace cullproof {

namespace {

using nlohmann::json;

// A float as the protocol writes it: the shortest decimal that reads back to it, unless reading
// that decimal as a double and rounding to float would not (double rounding); then the shortest
// decimal of the float's exact double value, which both readings recover exactly.
std::string number(float x) {
  const std::string d = format_float(x);
  if (float(std::strtod(d.c_str(), nullptr)) == x) return d;
  return fmt::format("{}", double(x));
}

std::string vec3(const glm::vec3& v) { return "[" + number(v.x) + ", " + number(v.y) + ", " + number(v.z) + "]"; }

std::string volume_text(const Volume& v) {
  return std::visit(
      [](const auto& x) -> std::string {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, Point>) return "{\"point\": " + vec3(x) + "}";
        else if constexpr (std::is_same_v<T, Sphere>)
          return "{\"sphere\": {\"center\": " + vec3(x.center) + ", \"radius\": " + number(x.radius) + "}}";
        else if constexpr (std::is_same_v<T, Aabb>)
          return "{\"aabb\": {\"min\": " + vec3(x.min) + ", \"max\": " + vec3(x.max) + "}}";
        else
          return "{\"obb\": {\"center\": " + vec3(x.center) + ", \"axes\": [" + vec3(x.axes[0]) + ", " + vec3(x.axes[1]) +
                 ", " + vec3(x.axes[2]) + "], \"half\": " + vec3(x.half) + "}}";
      },
      v);
}

std::string frustum_text(const CaseFrustum& f) {
  std::string s = "{\"planes\": [";
  for (int k = 0; k < kPlaneCount; ++k)
    s += (k ? ", [" : "[") + number(f.planes[k].n.x) + ", " + number(f.planes[k].n.y) + ", " + number(f.planes[k].n.z) +
         ", " + number(f.planes[k].d) + "]";
  s += "]";
  if (f.matrix) {
    s += ", \"matrix\": [";
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) s += (c || r ? ", " : "") + number((*f.matrix)[c][r]);
    s += fmt::format("], \"depth\": \"{}\", \"reversed_z\": {}",
                     f.depth.range == DepthRange::negative_one_to_one ? "negative_one_to_one" : "zero_to_one",
                     f.depth.reversed_z ? "true" : "false");
  }
  return s + "}";
}

using protocol::excerpt;

// A word of a command line as a POSIX shell reads it back: bare when it holds only characters no
// shell treats specially, else in single quotes.
std::string shell_word(const std::string& w) {
  const bool bare = !w.empty() && std::all_of(w.begin(), w.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("-_./=:,+@%", c) != nullptr;
  });
  if (bare) return w;
  std::string q = "'";
  for (char c : w) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// The running program: one request at a time (the methods' calls are serialised here). After a
// fault the program is stopped; a method's program is started again for the next call (restart),
// a system's is not (its state is gone).
class Process {
 public:
  explicit Process(ExternalOptions o) : opt_(std::move(o)) {
    if (opt_.command.empty()) throw std::runtime_error("external: no program given");
    name_ = shell_word(opt_.command[0]);
    for (std::size_t i = 1; i < opt_.command.size(); ++i) name_ += " " + shell_word(opt_.command[i]);
    start();
  }
  ~Process() { stop(/*polite=*/true); }
  const std::string& name() const { return name_; }

  // The handshake line, within the handshake's own time limit; the first one is kept, for restart().
  std::string read_handshake() {
    std::string h = read_line("the handshake", kMaxHandshakeBytes, "its handshake", "a handshake", opt_.handshake_timeout,
                              "--external-handshake-timeout");
    if (first_handshake_.empty()) first_handshake_ = h;
    return h;
  }

  // Starts the program again after a fault: the handshake it gave first must come back. Calls that
  // follow see a fresh program (generation() counts the starts, so that a stateful method's next
  // frame says reset).
  void restart() {
    const std::string after = dead_;
    stop(/*polite=*/false);
    dead_.clear();
    buffer_.clear();
    try {
      start();
      const std::string h = read_handshake();
      if (h != first_handshake_)
        fail("offered another handshake when started again than at first: " + excerpt(h));
    } catch (const std::runtime_error& e) {
      if (dead_.empty()) dead_ = e.what();
      throw std::runtime_error(fmt::format("external program '{}' could not be started again after a fault ({}): {}", name_,
                                           excerpt(after), e.what()));
    }
    ++generation_;
    next_frame = 1;  // a new process: its frames are numbered from 1 again
  }
  bool dead() const { return !dead_.empty(); }
  std::uint64_t generation() const { return generation_; }

 private:
  void start() {
    int in[2], out[2];
    if (::pipe(in) != 0 || ::pipe(out) != 0) throw std::runtime_error("external: cannot make pipes: " + std::string(std::strerror(errno)));
    std::signal(SIGPIPE, SIG_IGN);
    // Everything the child needs is made before fork(): between fork and exec it only calls the
    // system (another thread may hold the allocator's lock at the fork, which the child would wait
    // on forever).
    std::vector<char*> argv;
    for (std::string& a : opt_.command) argv.push_back(a.data());
    argv.push_back(nullptr);
    const std::string cannot_run = "external: cannot run '" + opt_.command.at(0) + "': ";
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("external: cannot fork: " + std::string(std::strerror(errno)));
    if (pid_ == 0) {
      // Its own process group: a Ctrl-C at the terminal stops cullproof (which then reports what
      // was judged and ends the program), not the program in the middle of an answer.
      ::setpgid(0, 0);
      ::dup2(in[0], 0);
      ::dup2(out[1], 1);
      ::close(in[0]), ::close(in[1]), ::close(out[0]), ::close(out[1]);
      ::execvp(argv[0], argv.data());
      const char* why = ::strerrordesc_np(errno);  // a constant text: no locale, no allocation
      (void)!::write(2, cannot_run.data(), cannot_run.size());
      if (why) (void)!::write(2, why, std::strlen(why));
      (void)!::write(2, "\n", 1);
      ::_exit(127);
    }
    ::close(in[0]);
    ::close(out[1]);
    to_ = in[1];
    from_ = out[0];
    ::fcntl(to_, F_SETFL, ::fcntl(to_, F_GETFL) | O_NONBLOCK);  // writes wait with the timeout too
  }

  // Ends the program: politely (bye, its input closed, half a second to exit) or at once.
  void stop(bool polite) {
    if (to_ >= 0) {
      if (polite) (void)write_all("{\"bye\": true}\n");
      ::close(to_);
      to_ = -1;
    }
    if (from_ >= 0) ::close(from_);
    from_ = -1;
    if (pid_ > 0) {
      int status = 0;
      for (int i = 0; polite && i < 50 && ::waitpid(pid_, &status, WNOHANG) == 0; ++i) ::usleep(10000);
      if (::waitpid(pid_, &status, WNOHANG) == 0) {
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, &status, 0);
      }
      pid_ = -1;
    }
  }

 public:
  // Reads one line of at most `max_bytes` within `timeout`; throws naming `what` was awaited
  // (and, for a longer line, `line_name` and `limit`: "its handshake", "a handshake"; for no
  // answer in time, the option that sets the limit).
  std::string read_line(const std::string& what, std::size_t max_bytes, const std::string& line_name,
                        const std::string& limit) {
    return read_line(what, max_bytes, line_name, limit, opt_.timeout, "--external-timeout");
  }
  std::string read_line(const std::string& what, std::size_t max_bytes, const std::string& line_name,
                        const std::string& limit, std::chrono::milliseconds timeout, const char* option) {
    std::size_t scanned = 0;  // the first `scanned` bytes of buffer_ hold no '\n'
    for (;;) {
      const auto nl = buffer_.find('\n', scanned);
      if (nl != std::string::npos && nl <= max_bytes) {
        std::string line = buffer_.substr(0, nl);
        buffer_.erase(0, nl + 1);
        return line;
      }
      if (nl != std::string::npos || buffer_.size() > max_bytes)
        fail(fmt::format("{} is a line longer than {}, the limit for {}: {}", line_name, byte_count_text(max_bytes), limit,
                         excerpt(buffer_)));
      scanned = buffer_.size();
      fill(what, timeout, option);
    }
  }

  // Reads what the program has written (at least a byte) into buffer_, within the timeout.
  void fill(const std::string& what) { fill(what, opt_.timeout, "--external-timeout"); }
  void fill(const std::string& what, std::chrono::milliseconds timeout, const char* option) {
    pollfd p{from_, POLLIN, 0};
    const int r = ::poll(&p, 1, int(timeout.count()));
    if (r == 0) fail(fmt::format("no answer within {} ms to {} (hung? the limit is {})", timeout.count(), what, option));
    if (r < 0) fail("cannot read its output: " + std::string(std::strerror(errno)));
    char chunk[65536];
    const ssize_t n = ::read(from_, chunk, sizeof chunk);
    if (n <= 0) fail(fmt::format("exited{} before answering {}", exit_status(), what));
    buffer_.append(chunk, std::size_t(n));
  }

  void send(const std::string& line, const std::string& what) { send_bytes(line + "\n", what); }
  void send_bytes(const std::string& bytes, const std::string& what) {
    if (!write_all(bytes)) fail(fmt::format("exited{} or stopped reading before it read {}", exit_status(), what));
  }

  // The first byte of the next answer, left to be read, within the timeout.
  char peek(const std::string& what) {
    if (buffer_.empty()) fill(what);
    return buffer_[0];
  }
  // Exactly n bytes of answer (a binary answer, whose size the question sets), within the timeout
  // for each read.
  std::string read_exact(std::size_t n, const std::string& what) {
    while (buffer_.size() < n) fill(what);
    std::string out = buffer_.substr(0, n);
    buffer_.erase(0, n);
    return out;
  }
  // After a binary answer of `size` bytes: bytes the program wrote past it, already here or
  // waiting in the pipe, are a fault of this answer (bytes that come later meet the next answer's
  // checks).
  void refuse_surplus(std::size_t size, const std::string& what) {
    pollfd p{from_, POLLIN, 0};
    if (buffer_.empty() && ::poll(&p, 1, 0) > 0 && (p.revents & POLLIN)) {
      char chunk[4096];
      const ssize_t n = ::read(from_, chunk, sizeof chunk);
      if (n > 0) buffer_.append(chunk, std::size_t(n));
    }
    if (!buffer_.empty())
      fail(fmt::format("wrote {} byte(s) or more past its binary answer to {} ({} bytes): {}", buffer_.size(), what, size,
                       excerpt(buffer_)));
  }

  // A fault: the program is stopped at once (a hung one too) and the call that met it throws;
  // only that call's method is at fault (restart() serves the next).
  [[noreturn]] void fail(const std::string& why) {
    if (dead_.empty()) dead_ = why;
    stop(/*polite=*/false);
    throw std::runtime_error("external program '" + name_ + "': " + why);
  }
  void check_alive() {
    if (!dead_.empty()) throw std::runtime_error("external program '" + name_ + "': not asked again after: " + dead_);
  }

  std::mutex mutex;
  std::uint64_t next_frame = 1;

 private:
  std::string dead_;
  std::uint64_t generation_ = 0;
  // False when the program is gone or has not read its input within the timeout.
  bool write_all(const std::string& s) {
    std::size_t done = 0;
    while (done < s.size()) {
      const ssize_t n = ::write(to_, s.data() + done, s.size() - done);
      if (n > 0) {
        done += std::size_t(n);
        continue;
      }
      if (n < 0 && errno == EAGAIN) {
        pollfd p{to_, POLLOUT, 0};
        if (::poll(&p, 1, int(opt_.timeout.count())) > 0 && !(p.revents & (POLLERR | POLLHUP))) continue;
      }
      return false;
    }
    return true;
  }
  std::string exit_status() {
    int status = 0;
    ::usleep(20000);
    if (::waitpid(pid_, &status, WNOHANG) != pid_) return "";
    pid_ = -1;
    if (WIFEXITED(status)) return fmt::format(" (status {})", WEXITSTATUS(status));
    if (WIFSIGNALED(status)) return fmt::format(" (signal {})", WTERMSIG(status));
    return "";
  }

  ExternalOptions opt_;
  std::string name_;
  pid_t pid_ = -1;
  int to_ = -1, from_ = -1;
  std::string buffer_;
  std::string first_handshake_;
};

struct External {
  std::vector<std::shared_ptr<Process>> processes;  // the program's copies; [0] for stateful methods
  std::string method;
  bool stateful = false;
  bool wants_reset = false;   // set by reset(): the next frame starts a camera path
  bool wants_matrix = false;  // asked only about frusta given by a clip matrix
  unsigned depths = 0xF;      // the depth conventions it reads (protocol::depth_convention_bit)
  bool binary = false;        // frames and answers in the binary encoding (version 3)
  std::uint32_t index = 0;    // its place in the handshake, which a binary frame names
  // Whether it is asked about frustum f at all (else it does not apply).
  bool applies(const CaseFrustum& f) const {
    if (wants_matrix && !f.matrix) return false;  // the case gives planes only
    return !wants_matrix || (depths & protocol::depth_convention_bit(f.depth));  // a convention it reads
  }
  // What the program reported of its own time ("ns" in answers), under own_mutex.
  std::mutex own_mutex;
  double own_ns = 0.0;
  std::uint64_t own_volumes = 0;
  std::atomic<std::size_t> next{0};  // where the search for a free copy starts
  std::uint64_t generation = 0;      // of processes[0], when a stateful method last asked it

  // A copy to ask, locked: the first copy for a stateful method, else the first free one from a
  // rotating start, else (all busy) the next in turn, waited for.
  std::pair<Process&, std::unique_lock<std::mutex>> acquire() {
    if (stateful || processes.size() == 1) return {*processes[0], std::unique_lock<std::mutex>(processes[0]->mutex)};
    const std::size_t start = next++ % processes.size();
    for (std::size_t k = 0; k < processes.size(); ++k) {
      Process& p = *processes[(start + k) % processes.size()];
      std::unique_lock<std::mutex> g(p.mutex, std::try_to_lock);
      if (g.owns_lock()) return {p, std::move(g)};
    }
    return {*processes[start], std::unique_lock<std::mutex>(processes[start]->mutex)};
  }
  // A copy to ask (acquire), started again if it was stopped; a stateful method's next frame then
  // asks the program to reset, since a program started again has forgotten every frame.
  std::pair<Process&, std::unique_lock<std::mutex>> acquire_running() {
    auto asked = acquire();
    Process& p = asked.first;
    if (p.dead()) p.restart();
    if (stateful && p.generation() != generation) {
      wants_reset = true;
      generation = p.generation();
    }
    return asked;
  }
  // Adds what the program reported of its own time.
  void add_own_time(double ns, std::uint64_t volumes) {
    std::lock_guard<std::mutex> g(own_mutex);
    own_ns += ns;
    own_volumes += volumes;
  }
};

// One frame message and its answer: verdicts for `volumes`, in order.
void ask(External& e, const CaseFrustum& f, const std::string* volumes, std::size_t n, Answer* out) {
  auto [p, lock] = e.acquire_running();
  const std::uint64_t id = p.next_frame++;
  std::string msg = fmt::format("{{\"frame\": {}, \"method\": {}, ", id, json(e.method).dump());
  if (e.wants_reset) msg += "\"reset\": true, ";
  e.wants_reset = false;
  msg += "\"frustum\": " + frustum_text(f) + ", \"volumes\": [";
  for (std::size_t i = 0; i < n; ++i) msg += (i ? ", " : "") + volumes[i];
  msg += "]}";
  const std::string what = fmt::format("frame {} ({} volume(s) for method '{}')", id, n, e.method);
  p.send(msg, what);
  const std::string line =
      p.read_line(what, kMaxAnswerBytes + n * kMaxAnswerBytesPerVolume, "its answer to " + what,
                  fmt::format("an answer about {} volume(s) ({} KiB and {} bytes a volume)", n, kMaxAnswerBytes >> 10,
                              kMaxAnswerBytesPerVolume));
  protocol::Reply r;
  try {
    r = protocol::parse_answer(line, id, n, what);
  } catch (const std::runtime_error& bad) {
    p.fail(bad.what());
  }
  if (r.ns) e.add_own_time(*r.ns, n);
  std::copy(r.verdicts.begin(), r.verdicts.end(), out);
}

// Frames in one binary message (an entry per run of volumes of one kind) and its answer: verdicts
// for every frame's volumes, frame after frame (std::nullopt for a frame it does not apply to).
void ask_binary(External& e, const FrameRequest* frames, std::size_t n, Answer* out) {
  auto [p, lock] = e.acquire_running();
  // The message is made in a buffer kept per thread (a chunk's message is hundreds of KiB: made
  // afresh each time, its pages would be mapped and unmapped per message).
  thread_local std::string entries;
  entries.clear();
  std::vector<protocol::AskedFrame> asked;
  std::vector<Answer*> to;  // where each entry's verdicts go
  std::size_t volumes = 0;
  for (std::size_t j = 0; j < n; ++j) {
    const FrameRequest& f = frames[j];
    Answer* here = out;
    out += f.count;
    if (!e.applies(*f.frustum)) {
      std::fill(here, here + f.count, Answer{});
      continue;
    }
    for (std::size_t a = 0, b = 0; a < f.count; a = b) {
      for (b = a + 1; b < f.count && f.volumes[b].index() == f.volumes[a].index(); ++b) {
      }
      const std::uint64_t id = p.next_frame++;
      if (entries.empty()) entries.resize(protocol::kBinaryFramesHeader);
      protocol::append_binary_frame(entries, id, e.index, e.wants_reset, *f.frustum, f.volumes + a, b - a);
      e.wants_reset = false;
      asked.push_back({id, b - a});
      to.push_back(here + a);
      volumes += b - a;
    }
  }
  if (asked.empty()) return;
  const std::string what =
      asked.size() == 1
          ? fmt::format("frame {} ({} volume(s) for method '{}')", asked[0].frame, volumes, e.method)
          : fmt::format("frames {} to {} ({} volume(s) for method '{}')", asked[0].frame, asked.back().frame, volumes, e.method);
  protocol::put_binary_header(entries, asked.size());
  p.send_bytes(entries, what);
  std::vector<protocol::Reply> replies;
  try {
    if (p.peek(what) == '{')
      protocol::refuse_json_instead_of_binary(
          p.read_line(what, kMaxAnswerBytes, "its answer to " + what, fmt::format("an error line ({} KiB)", kMaxAnswerBytes >> 10)),
          asked[0].frame, what);
    const std::size_t size = protocol::binary_answer_size(asked);
    std::string answer = p.read_exact(protocol::kBinaryAnswerHeader, what);
    protocol::check_binary_answer_header(answer, asked, what);
    answer += p.read_exact(size - answer.size(), what);
    replies = protocol::parse_binary_answer(answer, asked, what);
    p.refuse_surplus(size, what);
  } catch (const std::runtime_error& bad) {
    if (!p.dead()) p.fail(bad.what());
    throw;
  }
  double ns = 0.0;
  std::uint64_t timed = 0;
  for (std::size_t j = 0; j < replies.size(); ++j) {
    std::copy(replies[j].verdicts.begin(), replies[j].verdicts.end(), to[j]);
    if (replies[j].ns) ns += *replies[j].ns, timed += asked[j].volumes;
  }
  if (timed) e.add_own_time(ns, timed);
}

class Prepared : public BatchesByKind<Prepared> {
 public:
  Prepared(std::shared_ptr<External> e, CaseFrustum f) : e_(std::move(e)), f_(std::move(f)) {}
  Answer classify(const Volume& v) override {
    if (e_->binary) {
      Answer a;
      const FrameRequest one{&f_, &v, 1};
      ask_binary(*e_, &one, 1, &a);
      return a;
    }
    const std::string t = volume_text(v);
    Answer a;
    ask(*e_, f_, &t, 1, &a);
    return a;
  }

 private:
  friend class BatchesByKind<Prepared>;
  template <class K>
  void many(const K* v, std::size_t n, Answer* a) {
    if (n == 0) return;
    if (e_->binary) {
      const std::vector<Volume> volumes(v, v + n);
      const FrameRequest one{&f_, volumes.data(), n};
      return ask_binary(*e_, &one, 1, a);
    }
    std::vector<std::string> t;
    t.reserve(n);
    for (std::size_t i = 0; i < n; ++i) t.push_back(volume_text(Volume{v[i]}));
    ask(*e_, f_, t.data(), n, a);
  }
  std::shared_ptr<External> e_;
  CaseFrustum f_;
};

// ---- culling systems (protocol version 2)

std::string floats_text(const float* x, int n) {
  std::string s = "[";
  for (int i = 0; i < n; ++i) s += (i ? ", " : "") + number(x[i]);
  return s + "]";
}

std::string object_text(const SceneObject& o) {
  return fmt::format("{{\"id\": {}, \"world\": {}, \"local\": {}, \"transform\": {}}}", o.id, volume_text(o.world),
                     volume_text(o.local), floats_text(&o.transform[0][0], 16));
}

std::string view_text(const CullView& v) {
  return "{\"frustum\": " + frustum_text(v.frustum) + ", \"view\": " + floats_text(&v.view[0][0], 16) +
         ", \"projection\": " + floats_text(&v.projection[0][0], 16) + ", \"eye\": " + floats_text(&v.eye[0], 3) +
         ", \"axes\": " + floats_text(&v.axes[0][0], 9) + ", \"perspective\": " + (v.perspective ? "true" : "false") + "}";
}

// A system of the program: which scene it holds (the latest built), so that a state whose scene
// was replaced is not asked about another's.
struct ExternalSystem {
  std::shared_ptr<Process> process;
  SystemInfo info;
  std::uint64_t scene = 0;  // the number of the latest scene built
};

class ExternalSystemState final : public SystemState {
 public:
  ExternalSystemState(std::shared_ptr<ExternalSystem> s, const Scene& scene) : s_(std::move(s)) {
    std::string msg;
    for (const SceneObject& o : scene.objects)
      if (s_->info.takes(o.world)) msg += (objects_ ? ", " : "") + object_text(o), ++objects_;
    Process& p = *s_->process;
    std::lock_guard<std::mutex> g(p.mutex);
    p.check_alive();
    const std::uint64_t id = p.next_frame++;
    msg = fmt::format("{{\"frame\": {}, \"system\": {}, \"scene\": {{\"name\": {}, \"objects\": [", id,
                      json(s_->info.name).dump(), json(scene.name).dump()) +
          msg + "]}}";
    scene_ = s_->scene = id;
    exchange(p, msg, fmt::format("scene message {} ({} object(s) for system '{}')", id, objects_, s_->info.name),
             [&](const std::string& line, const std::string& what) { protocol::parse_acknowledgement(line, id, "built", what); });
  }

  void update(const std::vector<SceneObject>& moved) override {
    std::string list;
    std::size_t n = 0;
    for (const SceneObject& o : moved)
      if (s_->info.takes(o.world)) list += (n ? ", " : "") + object_text(o), ++n;
    if (n == 0) return;
    Process& p = *s_->process;
    std::lock_guard<std::mutex> g(p.mutex);
    check(p);
    const std::uint64_t id = p.next_frame++;
    exchange(p,
             fmt::format("{{\"frame\": {}, \"system\": {}, \"moved\": [{}]}}", id, json(s_->info.name).dump(), list),
             fmt::format("update message {} ({} moved object(s) for system '{}')", id, n, s_->info.name),
             [&](const std::string& line, const std::string& what) { protocol::parse_acknowledgement(line, id, "updated", what); });
  }

  void cull(const CullView& view, VisibleSet& out) override {
    Process& p = *s_->process;
    std::lock_guard<std::mutex> g(p.mutex);
    check(p);
    const std::uint64_t id = p.next_frame++;
    exchange(p, fmt::format("{{\"frame\": {}, \"system\": {}, \"view\": {}}}", id, json(s_->info.name).dump(), view_text(view)),
             fmt::format("cull message {} (system '{}', a scene of {} object(s))", id, s_->info.name, objects_),
             [&](const std::string& line, const std::string& what) {
               protocol::VisibleReply reply = protocol::parse_visible(line, id, objects_, s_->info.three_way, what);
               out = std::move(reply.set);
               last_ns_ = reply.ns ? *reply.ns : std::numeric_limits<double>::quiet_NaN();
             });
  }

  double last_cull_ns() const override { return last_ns_; }

 private:
  // Whether the program may be asked for this state: alive, and this state's scene still its.
  void check(Process& p) const {
    p.check_alive();
    if (s_->scene != scene_)
      throw std::logic_error("system '" + s_->info.name + "': its scene was replaced by a later build (one scene at a time "
                             "per system of a program)");
  }
  // Sends `msg` and hands the answer line to `read`; what it refuses is the program's fault.
  template <class Read>
  void exchange(Process& p, const std::string& msg, const std::string& what, Read read) {
    p.send(msg, what);
    const std::size_t limit = kMaxAnswerBytes + objects_ * kMaxAnswerBytesPerVolume;
    const std::string line = p.read_line(what, limit, "its answer to " + what,
                                         fmt::format("an answer about {} object(s) ({} KiB and {} bytes an object)", objects_,
                                                     kMaxAnswerBytes >> 10, kMaxAnswerBytesPerVolume));
    try {
      read(line, what);
    } catch (const std::runtime_error& bad) {
      p.fail(bad.what());
    }
  }

  std::shared_ptr<ExternalSystem> s_;
  double last_ns_ = std::numeric_limits<double>::quiet_NaN();  // the program's "ns" for the last cull
  std::uint64_t scene_ = 0;
  std::size_t objects_ = 0;
};

}  // namespace

std::vector<System> external_systems(const ExternalOptions& options) {
  auto process = std::make_shared<Process>(options);
  const std::string handshake = process->read_handshake();
  std::vector<System> out;
  for (SystemInfo& info : protocol::parse_offered_systems(handshake, process->name())) {
    info.program = process->name();
    auto s = std::make_shared<ExternalSystem>();
    s->process = process;
    s->info = info;
    out.emplace_back(std::move(info), [s](const Scene& scene) -> std::unique_ptr<SystemState> {
      return std::make_unique<ExternalSystemState>(s, scene);
    });
  }
  return out;
}

std::vector<Method> external_methods(const ExternalOptions& options) {
  if (options.instances < 1) throw std::invalid_argument("external: instances must be at least 1");
  std::vector<std::shared_ptr<Process>> processes;
  std::vector<std::string> handshakes;
  for (int i = 0; i < options.instances; ++i) {
    processes.push_back(std::make_shared<Process>(options));
    handshakes.push_back(processes.back()->read_handshake());
    if (handshakes.back() != handshakes[0])
      processes.back()->fail(fmt::format("copy {} of the program offered another handshake than the first: {}", i + 1,
                                         excerpt(handshakes.back())));
  }
  const std::shared_ptr<Process>& process = processes[0];
  std::vector<Method> out;
  for (protocol::OfferedMethod& offered : protocol::parse_handshake(handshakes[0], process->name())) {
    MethodInfo info = std::move(offered.info);
    info.program = process->name();
    auto e = std::make_shared<External>();
    e->processes = processes;
    e->method = info.name;
    e->stateful = info.stateful;
    e->wants_matrix = offered.wants_matrix;
    e->depths = offered.depths;
    e->binary = offered.binary;
    e->index = offered.index;
    Method method(
        info,
        [e](const CaseFrustum& f) -> std::unique_ptr<PreparedFrustum> {
          if (!e->applies(f)) return nullptr;
          return std::make_unique<Prepared>(e, f);
        },
        /*batch=*/true);
    // In the binary encoding, many frames go in one message (the campaign's frames of a chunk of
    // cases), so that a round trip is paid per message.
    if (e->binary && !e->stateful)
      method.on_frames([e](const FrameRequest* frames, std::size_t n, Answer* answers) { ask_binary(*e, frames, n, answers); });
    method.on_reset([e] { e->wants_reset = true; });
    method.on_own_timing([e] {
      std::lock_guard<std::mutex> g(e->own_mutex);
      const std::pair<double, std::uint64_t> r{e->own_ns, e->own_volumes};
      e->own_ns = 0.0;
      e->own_volumes = 0;
      return r;
    });
    out.push_back(std::move(method));
  }
  return out;
}

}  // namespace cullproof
