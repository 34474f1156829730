// The render side of the viewer: owns the renderer, the compiled world, the preview
// pacing and the film texture. Each frame it is told what to show (world from the
// document, view camera, film size). While the view moves, the frame's picture is
// traced right away, a coarse request (RenderSettings::step) to a second renderer on the
// workers of the one pool (the render is held meanwhile), as coarse as the measured
// cost of recent previews requires to fit the frame budget: a picture on every frame
// whatever the render is doing. When the view rests, the renderer refines it.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <vector>

#include "document.h"
#include "display.h"
#include "film_texture.h"
#include "film_view.h"
#include "texture_dirt.h"
#include "region.h"
#include "pacing.h"
#include "parallel.h"
#include "renderer.h"
#include "viewport.h"
#include "world.h"
#include "world_sync.h"

namespace rtview {

class RenderController {
public:
    // Renders on `pool` (the viewer's one pool, which must outlive it); aa_threshold:
    // adaptive anti-aliasing's (rt::RenderSettings), < 0 for none.
    RenderController(rt::ThreadPool& pool, bool interactive, int max_samples, double time_limit,
                     double aa_threshold);
    ~RenderController();

    // The document's scene changed (or not): its changes go into the world (world_sync.h:
    // in place where they can, else compiled anew off the UI thread while the last
    // world keeps rendering).
    void sync_world(const Document& doc);
    // Takes a world compiled elsewhere (a scene loaded in the background) for the
    // document's current content version.
    void adopt_world(std::shared_ptr<const rt::World> world, std::uint64_t content_version);
    // Drops the world (the document has no scene).
    void clear();

    // Starts or restarts the render for this view when anything changed. `moving`:
    // the view or a slider is being dragged, so a coarse preview within the frame
    // budget matters more than detail.
    void update(const rt::Camera& camera, int film_w, int film_h, bool moving);
    // Block size of the last preview traced on the UI thread (0: none yet).
    int last_preview_block() const { return preview_block_; }
    bool showing_preview() const { return showing_preview_; }
    // How the film is shown (exposure, tone curve, clipped overlay) and a render
    // region to show over it (null: none); used by upload().
    void set_display(const DisplaySettings& display, const RegionRenderer* region) {
        display_ = display;
        region_ = region;
    }
    // New film pixels to the texture. Call once per frame, after update().
    void upload();
    double last_upload_seconds() const { return upload_seconds_; }
    // The film's bytes and texture (for the picture tools, which draw them).
    FilmView& film_view() { return view_; }
    FilmTexture& texture() { return film_; }
    const rt::Renderer& renderer() const { return renderer_; }
    // Yield the processors (to a final render): pauses the render until called with false.
    void set_yield(bool y);
    // Draws the film into `image`.
    void draw(const Rect& image, float fb_scale);

    const rt::World* world() const { return sync_.world().get(); }
    const std::shared_ptr<const rt::World>& world_ptr() const { return sync_.world(); }
    bool building() const { return sync_.building(); }
    // The document's content version the world is compiled from.
    std::uint64_t world_version() const { return sync_.version(); }
    bool started() const { return started_world_ != nullptr; }
    // All requested samples are in and the texture shows the final film of this size.
    bool settled(int film_w, int film_h) const;
    // The picture on screen is of the document's content version `version`: the world
    // is compiled from it (not an older one kept on screen while it compiles) and the
    // render on that world has put its first pixels on the screen. Until then the
    // render's progress ("settled", "done") is another picture's.
    bool picture_current(std::uint64_t version) const;
    // Work is under way that needs display-rate frames.
    bool busy() const;
    // A view change is waiting for its first preview: poll faster than the display.
    bool awaiting_preview() const { return timing_change_ && renderer_.progress().running; }
    // The film has something the texture does not show yet (cheap: no pixels copied).
    bool has_new_picture() const;
    rt::RenderProgress progress() const { return renderer_.progress(); }
    rt::Image snapshot() const { return renderer_.snapshot(); }
    int threads() const { return renderer_.threads(); }

    int max_samples() const { return max_samples_; }
    double aa_threshold() const { return aa_threshold_; }
    void set_max_samples(int n);
    double time_limit() const { return time_limit_; }
    void set_time_limit(double s);
    bool paused() const { return paused_; }
    void set_paused(bool p);

    double done_elapsed() const { return done_elapsed_; }
    std::uint64_t done_generation() const { return done_generation_; }
    double last_latency_ms() const { return last_latency_ms_; }
    int last_coarse_block() const { return started_block_; }
    int preview_threads() const { return preview_.threads(); }  // tracing a moving view
    bool verbose = false;
    // Seconds since the program started (for --verbose timings of the first picture).
    double (*clock)() = nullptr;

private:
    void start(const rt::Camera& camera, int film_w, int film_h);
    void trace_preview(const rt::Camera& camera, int film_w, int film_h);
    // The world as seen from `position` (rt::with_camera_at: its camera buffer there),
    // made once per world and position: the last preview of a moving view and the
    // render started when the view rests share one.
    std::shared_ptr<const rt::World> world_at(const rt::Vec3& position);
    // The first image after a view change is on screen: the latency, said with
    // --verbose along with what made the image (`source`, taking `took` seconds).
    void first_image_after_change(const char* source, double took, int w, int h, int block);

    bool interactive_;
    rt::Renderer renderer_;
    rt::Renderer preview_;  // the previews of a moving view (one coarse pass each)
    PreviewPacer pacer_;
    WorldSync sync_;  // the compiled document scene

    // The render as last started.
    std::shared_ptr<const rt::World> started_world_;
    rt::Camera started_camera_;
    int started_w_ = 0, started_h_ = 0;
    int started_block_ = 8;
    std::uint64_t started_generation_ = 0;
    bool measured_ = false;       // its first coarse pass went into the pacer
    bool held_ = false;           // paused after its preview while the view moves
    std::chrono::steady_clock::time_point last_change_{};

    int max_samples_;
    double time_limit_;
    double aa_threshold_;
    bool settings_changed_ = false;
    bool paused_ = false;

    // The previews of a moving view.
    PreviewPacer ui_pacer_;
    FilmTexture preview_tex_;
    std::vector<std::uint8_t> preview_rgba_;
    bool showing_preview_ = false;  // the preview is on screen, not the film
    int preview_block_ = 0, preview_w_ = 0, preview_h_ = 0;  // of the film it previews
    // The world the preview shows, to compare with: not kept alive by it (a replaced
    // scene's memory is returned).
    std::weak_ptr<const rt::World> preview_world_;
    rt::Camera preview_camera_;
    // world_at()'s last answer, and the world and position it was made for.
    std::shared_ptr<const rt::World> at_;
    std::weak_ptr<const rt::World> at_world_;
    rt::Vec3 at_position_;

    FilmTexture film_;
    FilmView view_;
    // Pixels a frame sends to the film texture at most (4 MB): a 1920x1080 film in two
    // frames, a 2560x1600 one in four.
    static constexpr std::int64_t kUploadBudget = std::int64_t(1) << 20;
    TextureDirt dirt_;  // what of the film the texture does not have yet
    bool picture_due_ = false;  // the render has a picture; it shows once the texture has it all
    DisplaySettings display_;
    const RegionRenderer* region_ = nullptr;
    bool yield_ = false;
    std::uint64_t done_generation_ = ~std::uint64_t(0);
    std::uint64_t picture_generation_ = ~std::uint64_t(0);  // the render whose pixels are on screen
    double done_elapsed_ = 0;
    bool final_uploaded_ = false;
    bool first_picture_reported_ = false;
    std::array<std::uint64_t, 5> uploaded_sig_{};  // progress signature of the last upload
    // Timing of "a view change -> coarse image on screen" (printed with --verbose).
    std::chrono::steady_clock::time_point change_time_{};
    bool timing_change_ = false;
    double last_latency_ms_ = -1;
    double upload_seconds_ = 0;
};

}  // namespace rtview
