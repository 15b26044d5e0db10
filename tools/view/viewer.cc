#include "tools/view/viewer.h"

#include <spdlog/spdlog.h>

#include <SFML/Graphics.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "protocol/dispatcher.h"
#include "tools/view/png_writer.h"
#include "tools/view/policy_drawing.h"
#include "tools/view/safe_name.h"

namespace dynapath::view {
namespace {

constexpr int kStatusScale = 1;
constexpr int kStatusHeight = kStatusScale * (2 * kLineHeight + 4);
const sf::Color kBackdrop(24, 26, 32);

// RGB picture -> RGBA texture (re-created when the size changes).
void Upload(const RgbImage& image, sf::Texture& texture) {
  const auto width = static_cast<unsigned>(image.width());
  const auto height = static_cast<unsigned>(image.height());
  if (texture.getSize() != sf::Vector2u(width, height)) texture.create(width, height);
  std::vector<sf::Uint8> rgba(static_cast<size_t>(width) * height * 4);
  const std::vector<uint8_t>& rgb = image.bytes();
  for (size_t i = 0, n = static_cast<size_t>(width) * height; i < n; ++i) {
    rgba[4 * i] = rgb[3 * i];
    rgba[4 * i + 1] = rgb[3 * i + 1];
    rgba[4 * i + 2] = rgb[3 * i + 2];
    rgba[4 * i + 3] = 255;
  }
  texture.update(rgba.data());
}

std::string ElideTo(std::string text, int width_px, int scale) {
  const int fits = std::max(0, (width_px - 6 * scale) / (kGlyphAdvance * scale));
  if (static_cast<int>(text.size()) > fits) text.resize(static_cast<size_t>(fits));
  return text;
}

class Viewer {
 public:
  Viewer(PolicyFeed& feed, const ViewerOptions& options)
      : feed_(feed),
        options_(options),
        follow_(options.approach.empty()),
        wanted_(options.approach),
        window_(sf::VideoMode(static_cast<unsigned>(options.window_width),
                              static_cast<unsigned>(options.window_height)),
                "dynapath view") {
    window_.setFramerateLimit(30);
  }

  int Run() {
    const std::atomic<bool>& stop = protocol::StopOnSignals();
    const auto start = std::chrono::steady_clock::now();
    while (window_.isOpen()) {
      if (stop) break;
      HandleEvents();
      if (!window_.isOpen()) break;
      Refresh();
      Draw();
      // The count the status line shows: the screenshot shows what it says.
      if (!options_.screenshot.empty() && have_policy_ && received_ >= options_.screenshot_after) {
        return SaveScreenshot();
      }
      window_.display();
      const double elapsed =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (!options_.screenshot.empty() && elapsed > options_.timeout_seconds) {
        spdlog::error("received {} of {} policies within {:.0f} s; no screenshot taken",
                      feed_.received(), options_.screenshot_after, options_.timeout_seconds);
        return 1;
      }
    }
    return 0;
  }

 private:
  sf::Vector2f Area() const {
    const sf::Vector2u size = window_.getSize();
    return {static_cast<float>(size.x),
            std::max(1.0f, static_cast<float>(size.y) - static_cast<float>(kStatusHeight))};
  }

  void Fit() {
    if (!have_policy_) return;
    const sf::Vector2f area = Area();
    const sf::Vector2u size = texture_.getSize();
    float zoom = std::min(area.x / static_cast<float>(size.x), area.y / static_cast<float>(size.y));
    if (zoom >= 1.0f) zoom = std::floor(zoom);  // whole pixels stay crisp
    zoom_ = zoom;
    offset_ = {std::round((area.x - static_cast<float>(size.x) * zoom_) / 2),
               std::round((area.y - static_cast<float>(size.y) * zoom_) / 2)};
  }

  // Zoom by `factor` keeping the picture point under `at` in place.
  void ZoomAbout(float factor, sf::Vector2f at) {
    const float zoom = std::clamp(zoom_ * factor, 0.05f, 64.0f);
    offset_ = at - (at - offset_) * (zoom / zoom_);
    zoom_ = zoom;
  }

  void Select(int index) {
    const std::vector<std::string> approaches = feed_.approaches();
    if (approaches.empty()) return;
    const int n = static_cast<int>(approaches.size());
    wanted_ = approaches[static_cast<size_t>(((index % n) + n) % n)];
    follow_ = false;
    dirty_ = true;
  }

  int ShownIndex() const {
    const std::vector<std::string> approaches = feed_.approaches();
    auto it = std::find(approaches.begin(), approaches.end(), shown_);
    return it == approaches.end() ? -1 : static_cast<int>(it - approaches.begin());
  }

  void HandleEvents() {
    sf::Event event;
    while (window_.pollEvent(event)) {
      switch (event.type) {
        case sf::Event::Closed:
          window_.close();
          return;
        case sf::Event::Resized:
          window_.setView(sf::View(sf::FloatRect(0, 0, static_cast<float>(event.size.width),
                                                 static_cast<float>(event.size.height))));
          status_text_.clear();
          if (options_.cell_px == 0) cell_ = 0;  // cells to fit the new size
          dirty_ = true;
          refit_ = true;
          break;
        case sf::Event::KeyPressed:
          OnKey(event.key);
          break;
        case sf::Event::MouseWheelScrolled:
          ZoomAbout(std::pow(1.25f, event.mouseWheelScroll.delta),
                    sf::Vector2f(static_cast<float>(event.mouseWheelScroll.x),
                                 static_cast<float>(event.mouseWheelScroll.y)));
          break;
        case sf::Event::MouseButtonPressed:
          if (event.mouseButton.button == sf::Mouse::Left) {
            dragging_ = true;
            drag_from_ = {event.mouseButton.x, event.mouseButton.y};
          }
          break;
        case sf::Event::MouseButtonReleased:
          if (event.mouseButton.button == sf::Mouse::Left) dragging_ = false;
          break;
        case sf::Event::MouseMoved:
          if (dragging_) {
            const sf::Vector2i at(event.mouseMove.x, event.mouseMove.y);
            offset_ += sf::Vector2f(static_cast<float>(at.x - drag_from_.x),
                                    static_cast<float>(at.y - drag_from_.y));
            drag_from_ = at;
          }
          break;
        default:
          break;
      }
    }
  }

  void OnKey(const sf::Event::KeyEvent& key) {
    const sf::Vector2f centre = Area() / 2.0f;
    constexpr float kPan = 40.0f;
    switch (key.code) {
      case sf::Keyboard::Escape:
      case sf::Keyboard::Q:
        window_.close();
        break;
      case sf::Keyboard::Tab:
        Select(ShownIndex() + (key.shift ? -1 : 1));
        break;
      case sf::Keyboard::PageDown:
        Select(ShownIndex() + 1);
        break;
      case sf::Keyboard::PageUp:
        Select(ShownIndex() - 1);
        break;
      case sf::Keyboard::A:
        follow_ = true;
        dirty_ = true;
        break;
      case sf::Keyboard::F:
      case sf::Keyboard::Num0:
        Fit();
        break;
      case sf::Keyboard::Add:
      case sf::Keyboard::Equal:
        ZoomAbout(1.25f, centre);
        break;
      case sf::Keyboard::Subtract:
      case sf::Keyboard::Hyphen:
        ZoomAbout(0.8f, centre);
        break;
      case sf::Keyboard::Left:
        offset_.x += kPan;
        break;
      case sf::Keyboard::Right:
        offset_.x -= kPan;
        break;
      case sf::Keyboard::Up:
        offset_.y += kPan;
        break;
      case sf::Keyboard::Down:
        offset_.y -= kPan;
        break;
      default:
        if (key.code >= sf::Keyboard::Num1 && key.code <= sf::Keyboard::Num9) {
          Select(key.code - sf::Keyboard::Num1);
        }
        break;
    }
  }

  // Picks the policy to show and redraws it when it changed.
  void Refresh() {
    const int64_t version = feed_.version();
    if (version == seen_version_ && !dirty_) return;
    seen_version_ = version;
    received_ = feed_.received();  // before taking the policy: never more than shown
    dirty_ = false;
    std::string approach = follow_ ? feed_.LastApproach() : wanted_;
    if (!follow_) {
      // --approach may name an approach by its directory name (A_Oracle).
      for (const std::string& name : feed_.approaches()) {
        if (name == wanted_ || SafeName(name) == wanted_) approach = name;
      }
    }
    std::optional<policy_t> policy = feed_.Latest(approach);
    if (!policy) return;
    shown_ = approach;
    step_ = policy->time_step;
    if (options_.cell_px > 0) {
      cell_ = options_.cell_px;
    } else if (cell_ == 0 || policy->rows != rows_ || policy->cols != cols_) {
      // Cells as large as fit the window (up to 48 px): the picture is drawn
      // at its size, arrows sharp, rather than scaled. --cell overrides.
      const sf::Vector2f area = Area();
      const int header = 2 * (2 * kLineHeight + 4);
      const int fit = std::min(static_cast<int>(area.x) / std::max(1, policy->cols),
                               (static_cast<int>(area.y) - header) / std::max(1, policy->rows));
      cell_ = std::clamp(fit, 1, 48);
    }
    rows_ = policy->rows;
    cols_ = policy->cols;
    const RgbImage image = DrawPolicy(*policy, DrawOptions{cell_, true});
    const bool resized = texture_.getSize() != sf::Vector2u(static_cast<unsigned>(image.width()),
                                                            static_cast<unsigned>(image.height()));
    Upload(image, texture_);
    sprite_.setTexture(texture_, true);
    const bool first = !have_policy_;
    have_policy_ = true;
    if (first || resized || refit_) Fit();
    refit_ = false;
  }

  void DrawStatus() {
    const std::vector<std::string> approaches = feed_.approaches();
    std::string line;
    if (!have_policy_) {
      const std::string run = feed_.run();
      line = "waiting for policies on DYNAPATH/" + (run.empty() ? std::string("*") : run) +
             "/POLICY (" + options_.lcm_url + ")";
      if (!follow_) line += ", approach " + wanted_;
    } else {
      line = "run " + feed_.run() + "  |  approach " + std::to_string(ShownIndex() + 1) + "/" +
             std::to_string(approaches.size()) + ": " + shown_ + (follow_ ? " (following)" : "") +
             "  |  step " + std::to_string(step_) + "  |  " + std::to_string(received_) +
             " policies, " + std::to_string(feed_.dropped()) + " dropped  |  zoom " +
             std::to_string(static_cast<int>(std::lround(zoom_ * 100))) + "%";
    }
    const std::string keys =
        "Tab/1-9: approach  A: follow latest  wheel,+,-: zoom  drag,arrows: pan  F: fit  Q: quit";
    const int width = static_cast<int>(window_.getSize().x);
    const std::string text = line + "\n" + keys;
    if (text != status_text_) {
      status_text_ = text;
      RgbImage bar(std::max(1, width), kStatusHeight, colour::kHeader);
      DrawText(bar, 3, 3, ElideTo(line, width, kStatusScale), kStatusScale, colour::kHeaderText);
      DrawText(bar, 3, 3 + kLineHeight * kStatusScale, ElideTo(keys, width, kStatusScale),
               kStatusScale, colour::kGridLine);
      Upload(bar, status_texture_);
      status_sprite_.setTexture(status_texture_, true);
    }
    status_sprite_.setPosition(0, static_cast<float>(window_.getSize().y) - kStatusHeight);
    window_.draw(status_sprite_);
  }

  void Draw() {
    window_.clear(kBackdrop);
    if (have_policy_) {
      sprite_.setPosition(std::round(offset_.x), std::round(offset_.y));
      sprite_.setScale(zoom_, zoom_);
      window_.draw(sprite_);
    }
    DrawStatus();
  }

  int SaveScreenshot() {
    const sf::Vector2u size = window_.getSize();
    sf::Texture capture;
    if (!capture.create(size.x, size.y)) {
      spdlog::error("cannot capture the window");
      return 1;
    }
    capture.update(window_);
    const sf::Image shot = capture.copyToImage();
    RgbImage image(static_cast<int>(size.x), static_cast<int>(size.y));
    const sf::Uint8* rgba = shot.getPixelsPtr();
    for (unsigned y = 0; y < size.y; ++y) {
      for (unsigned x = 0; x < size.x; ++x) {
        const sf::Uint8* p = rgba + 4 * (static_cast<size_t>(y) * size.x + x);
        image.Set(static_cast<int>(x), static_cast<int>(y), Rgb{p[0], p[1], p[2]});
      }
    }
    if (Status status = WritePng(options_.screenshot, image); !status) {
      spdlog::error("{}", status.error().message);
      return 1;
    }
    spdlog::info("saved the window ({}x{}, {} of run {} at step {}) to {}", size.x, size.y, shown_,
                 feed_.run(), step_, options_.screenshot);
    return 0;
  }

  PolicyFeed& feed_;
  const ViewerOptions& options_;
  bool follow_;
  std::string wanted_, shown_;
  sf::RenderWindow window_;
  sf::Texture texture_, status_texture_;
  sf::Sprite sprite_, status_sprite_;
  std::string status_text_;
  int64_t seen_version_ = -1;
  int64_t received_ = 0;  // policies received when the shown one was taken
  bool dirty_ = true;
  bool refit_ = false;
  int cell_ = 0;  // pixels per cell of the picture (0: choose)
  int rows_ = 0, cols_ = 0;
  bool have_policy_ = false;
  int step_ = 0;
  float zoom_ = 1.0f;
  sf::Vector2f offset_{0, 0};
  bool dragging_ = false;
  sf::Vector2i drag_from_{0, 0};
};

}  // namespace

int RunViewer(PolicyFeed& feed, const ViewerOptions& options) {
  Viewer viewer(feed, options);
  return viewer.Run();
}

}  // namespace dynapath::view
