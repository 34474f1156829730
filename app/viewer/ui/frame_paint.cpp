// Whole and partial frames (see frame_paint.h).
#include "frame_paint.h"

#include <GL/gl.h>
#include <imgui.h>
#include <imgui_impl_opengl2.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string_view>

#include "film_texture.h"

namespace rtview {

namespace {

// Texture changes since the last frame painted.
std::vector<TextureChange>& texture_changes() {
    static std::vector<TextureChange> changes;
    return changes;
}

// The frame's triangles, list by list, in framebuffer pixels; false if a list holds a
// callback (drawing this comparison cannot see).
bool frame_triangles(const ImDrawData& data, std::vector<DrawTriangles>& lists) {
    const ImVec2 off = data.DisplayPos, scale = data.FramebufferScale;
    lists.resize(std::size_t(data.CmdListsCount));
    for (int n = 0; n < data.CmdListsCount; ++n) {
        const ImDrawList& l = *data.CmdLists[n];
        DrawTriangles& out = lists[std::size_t(n)];
        out.clear();
        // Lists are matched by their window's name from frame to frame.
        out.id = l._OwnerName ? std::hash<std::string_view>()(l._OwnerName) : ~std::uint64_t(n);
        out.reserve(std::size_t(l.IdxBuffer.Size));
        for (const ImDrawCmd& cmd : l.CmdBuffer) {
            if (cmd.UserCallback) return false;
            DrawVertex d;
            d.clip[0] = (cmd.ClipRect.x - off.x) * scale.x, d.clip[1] = (cmd.ClipRect.y - off.y) * scale.y;
            d.clip[2] = (cmd.ClipRect.z - off.x) * scale.x, d.clip[3] = (cmd.ClipRect.w - off.y) * scale.y;
            d.texture = std::uint64_t(reinterpret_cast<std::uintptr_t>(cmd.TextureId));
            for (unsigned i = 0; i < cmd.ElemCount; ++i) {
                const ImDrawVert& v = l.VtxBuffer[int(cmd.VtxOffset + l.IdxBuffer[int(cmd.IdxOffset + i)])];
                d.x = (v.pos.x - off.x) * scale.x, d.y = (v.pos.y - off.y) * scale.y;
                d.u = v.uv.x, d.v = v.uv.y, d.colour = v.col;
                out.push_back(d);
            }
        }
    }
    return true;
}

// A command's scissor as ImGui's OpenGL2 backend sets it (framebuffer pixels, top row
// 0), cut to `box`, written back as a clip rectangle from which the backend makes
// exactly that scissor (its float-to-int truncations given slack both ways).
ImVec4 clip_within(const ImVec4& clip, const PixelBox& box, const ImDrawData& data, int height) {
    const ImVec2 off = data.DisplayPos, scale = data.FramebufferScale;
    const float cx0 = (clip.x - off.x) * scale.x, cy0 = (clip.y - off.y) * scale.y;
    const float cx1 = (clip.z - off.x) * scale.x, cy1 = (clip.w - off.y) * scale.y;
    if (cx1 <= cx0 || cy1 <= cy0) return clip;
    const int sx = int(cx0), sw = int(cx1 - cx0), sy = int(float(height) - cy1), sh = int(cy1 - cy0);
    const int x0 = std::max(sx, box.x0), x1 = std::min(sx + sw, box.x1);
    const int y0 = std::max(height - sy - sh, box.y0), y1 = std::min(height - sy, box.y1);
    if (x1 <= x0 || y1 <= y0) return ImVec4(0, 0, 0, 0);  // nothing: the backend skips it
    return ImVec4((float(x0) + 0.25f) / scale.x + off.x, (float(y0) - 0.5f) / scale.y + off.y,
                  (float(x1) + 0.5f) / scale.x + off.x, (float(y1) - 0.25f) / scale.y + off.y);
}

void clear(int width, int height, const PixelBox* box) {
    glViewport(0, 0, width, height);
    glClearColor(kClearColour[0], kClearColour[1], kClearColour[2], kClearColour[3]);
    if (box) {
        glEnable(GL_SCISSOR_TEST);
        glScissor(box->x0, height - box->y1, box->x1 - box->x0, box->y1 - box->y0);
    }
    glClear(GL_COLOR_BUFFER_BIT);
    glDisable(GL_SCISSOR_TEST);
}

// The frame within each box: cleared there, and every command clipped to it.
void paint_boxes(ImDrawData* data, const std::vector<PixelBox>& boxes, int width, int height) {
    std::vector<ImVec4> clips;
    for (int n = 0; n < data->CmdListsCount; ++n)
        for (const ImDrawCmd& cmd : data->CmdLists[n]->CmdBuffer) clips.push_back(cmd.ClipRect);
    for (const PixelBox& box : boxes) {
        clear(width, height, &box);
        std::size_t k = 0;
        for (int n = 0; n < data->CmdListsCount; ++n)
            for (ImDrawCmd& cmd : data->CmdLists[n]->CmdBuffer) cmd.ClipRect = clip_within(clips[k++], box, *data, height);
        ImGui_ImplOpenGL2_RenderDrawData(data);
    }
    std::size_t k = 0;
    for (int n = 0; n < data->CmdListsCount; ++n)
        for (ImDrawCmd& cmd : data->CmdLists[n]->CmdBuffer) cmd.ClipRect = clips[k++];
}

}  // namespace

void note_texture_change(std::uint64_t texture, int width, int height, const PixelBox& texels) {
    if (width < 1 || height < 1 || texels.empty()) return;
    // A texel filtered linearly shows on the screen pixels up to a texel away.
    texture_changes().push_back({texture, float(texels.x0 - 1) / float(width), float(texels.y0 - 1) / float(height),
                                 float(texels.x1 + 1) / float(width), float(texels.y1 + 1) / float(height)});
}

void paint_whole(ImDrawData* data, int width, int height) {
    texture_changes().clear();
    clear(width, height, nullptr);
    ImGui_ImplOpenGL2_RenderDrawData(data);
}

const std::vector<PixelBox>& FramePainter::paint(ImDrawData* data, int width, int height) {
    std::vector<DrawTriangles> lists;
    const bool comparable = partial_ && frame_triangles(*data, lists);
    if (!comparable) damage_.invalidate();
    boxes_ = damage_.compare(std::move(lists), width, height, texture_changes());
    if (!comparable) damage_.invalidate();  // (what it keeps is not this frame)
    if (!partial_ || (boxes_.size() == 1 && boxes_[0] == PixelBox{0, 0, width, height})) {
        paint_whole(data, width, height);
        boxes_.assign(1, PixelBox{0, 0, width, height});
        return boxes_;
    }
    texture_changes().clear();
    paint_boxes(data, boxes_, width, height);
    if (check_) check(data, width, height);
    return boxes_;
}

void FramePainter::check(ImDrawData* data, int width, int height) {
    const std::vector<std::uint8_t> partial = read_framebuffer(width, height);
    paint_whole(data, width, height);
    const std::vector<std::uint8_t> whole = read_framebuffer(width, height);
    long n = 0;
    int y0 = height, y1 = -1;
    for (std::size_t i = 0; i < whole.size(); ++i)
        if (whole[i] != partial[i]) {
            ++n;
            const int y = int(i / (std::size_t(width) * 3));
            y0 = std::min(y0, y), y1 = std::max(y1, y);
        }
    ++checked_;
    if (n == 0) return;
    ++differed_;
    std::fprintf(stderr, "raytracer-view: a partial frame differs from the whole frame in %ld bytes, rows %d..%d (%zu boxes)\n",
                 n, y0, y1, boxes_.size());
}

}  // namespace rtview
