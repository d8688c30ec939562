// The campaign's progress line (see campaign_internal.hpp).
#include "campaign_internal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <unistd.h>

namespace cullproof::detail {

Progress::Progress(bool on, std::uint64_t total) : on_(on), total_(total), tty_(::isatty(2) != 0) {
  if (on_) thread_ = std::thread([this] { loop(); });
}

void Progress::label(std::string s) {
  std::lock_guard<std::mutex> g(m_);
  label_ = std::move(s);
}

void Progress::print(const std::function<void()>& f) {
  std::lock_guard<std::mutex> g(out_);
  if (on_ && tty_ && !finished_) std::cerr << "\r\033[K" << std::flush;
  f();
  std::cout << std::flush;
  if (on_ && tty_ && !finished_) draw_locked(false);
}

void Progress::finish() {
  if (!thread_.joinable()) return;
  {
    std::lock_guard<std::mutex> g(m_);
    stop_ = true;
  }
  cv_.notify_all();
  thread_.join();
  std::lock_guard<std::mutex> g(out_);
  draw_locked(true);
  finished_ = true;
}

void Progress::loop() {
  std::unique_lock<std::mutex> g(m_);
  while (!stop_) {
    cv_.wait_for(g, std::chrono::milliseconds(tty_ ? 200 : 1000));
    if (stop_) break;
    g.unlock();
    draw(false);
    g.lock();
  }
}

void Progress::draw(bool last) {
  std::lock_guard<std::mutex> g(out_);
  draw_locked(last);
}

void Progress::draw_locked(bool last) {
  const std::uint64_t d = std::min(done_.load(), total_);
  const double f = total_ ? double(d) / double(total_) : 1.0;
  const double secs = std::chrono::duration<double>(Clock::now() - start_).count();
  std::string lbl;
  {
    std::lock_guard<std::mutex> g(m_);
    lbl = label_;
  }
  if (tty_) {
    const int w = 30, filled = int(f * w);
    std::cerr << fmt::format("\r[{}{}] {:5.1f}% {}/{} cases {:.0f}s {:<24}", std::string(filled, '#'),
                             std::string(w - filled, '.'), 100 * f, d, total_, secs, lbl)
              << (last ? "\n" : "") << std::flush;
  } else {
    const int decile = int(f * 10);
    if (decile > last_decile_ || last) {
      last_decile_ = decile;
      std::cerr << fmt::format("verify: {:3.0f}% ({}/{} cases, {:.0f}s) {}\n", 100 * f, d, total_, secs, lbl);
    }
  }
}

}  // namespace cullproof::detail
