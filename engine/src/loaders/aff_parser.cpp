#include "aff_parser.h"

#include <charconv>
#include <fstream>
#include <sstream>
#include <utility>

#include "dynrt/scene/scene_error.h"
#include "message_text.h"

namespace dynrt::aff {

using dynrt::cat;

const Animation* AffModel::find_animation(std::string_view name) const {
    for (const Animation& a : animations)
        if (a.name == name) return &a;
    return nullptr;
}

namespace {

struct Token {
    std::string_view text;
    int line = 0;
};

// Whitespace-separated tokens with their line numbers. AFF commands span lines freely (`v`,
// `xs`, `fm` and every block), so the parser reads tokens, not lines; a token that starts
// with '#' or '%' comments out the rest of its line.
class Lexer {
public:
    Lexer(std::string_view text, std::string file) : text_(text), file_(std::move(file)) {}

    const std::string& file() const { return file_; }

    std::optional<Token> peek() {
        if (!peeked_) peeked_ = scan();
        return *peeked_;
    }

    std::optional<Token> next() {
        std::optional<Token> t = peek();
        peeked_.reset();
        if (t) last_line_ = t->line;
        return t;
    }

    /// The line of the last token read, for messages about what is missing after it.
    int last_line() const { return last_line_; }

    [[noreturn]] void fail(int line, const std::string& what) const {
        throw SceneError(cat(file_, ":", line, ": ", what));
    }

private:
    std::optional<Token> scan() {
        for (;;) {
            while (pos_ < text_.size() && is_space(text_[pos_])) {
                if (text_[pos_] == '\n') ++line_;
                ++pos_;
            }
            if (pos_ >= text_.size()) return std::nullopt;
            if (text_[pos_] == '#' || text_[pos_] == '%') {
                while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
                continue;
            }
            const std::size_t start = pos_;
            while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
            return Token{text_.substr(start, pos_ - start), line_};
        }
    }

    static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }

    std::string_view text_;
    std::string file_;
    std::size_t pos_ = 0;
    int line_ = 1;
    int last_line_ = 1;
    std::optional<std::optional<Token>> peeked_;
};

std::optional<float> to_float(std::string_view s) {
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    float v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
    return v;
}

bool is_number(const std::optional<Token>& t) { return t && to_float(t->text).has_value(); }

constexpr int include_depth_max = 64;

class Parser {
public:
    explicit Parser(AffModel& model) : model_(model) {
        model_.nodes.push_back(TransformNode{});  // the root
    }

    void parse_file(const std::filesystem::path& path, const std::string& included_from) {
        // Only regular files: an include naming a device (/dev/zero) or a folder would never end
        // or never parse.
        std::error_code ec;
        if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
            throw SceneError(cat(included_from, "not a regular file: ", path.string()));
        std::ifstream in(path, std::ios::binary);
        if (!in) throw SceneError(cat(included_from, "cannot open AFF file ", path.string()));
        std::ostringstream text;
        text << in.rdbuf();
        parse_text(text.str(), path);
    }

    void parse_text(std::string_view text, const std::filesystem::path& path) {
        if (static_cast<int>(active_.size()) >= include_depth_max)
            throw SceneError(cat(path.string(), ": includes nested deeper than ", include_depth_max, " (an include cycle?)"));
        model_.files.push_back(path.string());
        active_.push_back(path.lexically_normal());
        Lexer lex(text, path.string());
        while (std::optional<Token> t = lex.next()) command(lex, *t, path);
        active_.pop_back();
    }

    void finish() {
        if (!open_.empty()) {
            const SourceLocation& w = model_.nodes[static_cast<std::size_t>(open_.back())].where;
            throw SceneError(cat(w.file, ":", w.line, ": transform block '{' is never closed with '}'"));
        }
    }

private:
    // ---- token helpers: every failure names the command being read ----
    Token need(Lexer& lex, std::string_view what) {
        std::optional<Token> t = lex.next();
        if (!t) lex.fail(lex.last_line(), cat("unexpected end of file: expected ", what));
        return *t;
    }

    float number(Lexer& lex, std::string_view cmd) {
        const Token t = need(lex, cat("a number for '", cmd, "'"));
        const std::optional<float> v = to_float(t.text);
        if (!v) lex.fail(t.line, cat("'", cmd, "' expects a number, found '", t.text, "'"));
        return *v;
    }

    int count(Lexer& lex, std::string_view cmd, int min = 0) {
        const Token t = need(lex, cat("a count for '", cmd, "'"));
        int v = 0;
        const auto [end, ec] = std::from_chars(t.text.data(), t.text.data() + t.text.size(), v);
        if (ec != std::errc() || end != t.text.data() + t.text.size() || v < min)
            lex.fail(t.line, cat("'", cmd, "' expects a whole number >= ", min, ", found '", t.text, "'"));
        return v;
    }

    Vec3 vec3(Lexer& lex, std::string_view cmd) {
        Vec3 v{};
        for (float& c : v) c = number(lex, cmd);
        return v;
    }

    Vec2 vec2(Lexer& lex, std::string_view cmd) {
        Vec2 v{};
        for (float& c : v) c = number(lex, cmd);
        return v;
    }

    void keyword(Lexer& lex, std::string_view kw, std::string_view cmd) {
        const Token t = need(lex, cat("'", kw, "' in '", cmd, "'"));
        if (t.text != kw)
            lex.fail(t.line, cat("'", cmd, "' expects '", kw, "', found '", t.text, "'"));
    }

    void open_brace(Lexer& lex, std::string_view cmd) { keyword(lex, "{", cmd); }

    // A name: any token but a number or a brace, so a forgotten name is reported at its place.
    std::string word(Lexer& lex, std::string_view what, std::string_view cmd) {
        const Token t = need(lex, cat(what, " for '", cmd, "'"));
        if (to_float(t.text) || t.text == "{" || t.text == "}")
            lex.fail(t.line, cat("'", cmd, "' expects ", what, ", found '", t.text, "'"));
        return std::string(t.text);
    }

    // An optional name or texture: present when the next token is not a number.
    std::string optional_word(Lexer& lex) {
        const std::optional<Token> t = lex.peek();
        if (!t || is_number(t) || t->text == "{" || t->text == "}") return {};
        lex.next();
        return std::string(t->text);
    }

    template <class T>
    T placed(const Lexer& lex, int line) {
        T shape;
        shape.material = static_cast<int>(model_.materials.size()) - 1;
        shape.node = open_.empty() ? 0 : open_.back();
        shape.where = {lex.file(), line};
        return shape;
    }

    // ---- commands ----
    void command(Lexer& lex, const Token& t, const std::filesystem::path& path) {
        const std::string_view c = t.text;
        if (c == "v") return view(lex);
        if (c == "b") return void(model_.background = vec3(lex, c));
        if (c == "am") return void(model_.ambient = vec3(lex, c));
        if (c == "l" || c == "la") return light(lex, c);
        if (c == "f" || c == "fm") return material(lex, c);
        if (c == "p" || c == "pp") return polygon(lex, t);
        if (c == "tt" || c == "ttp") return textured_triangle(lex, t);
        if (c == "s") return sphere(lex, t);
        if (c == "c") return cone(lex, t);
        if (c == "m") return mesh(lex, t);
        if (c == "tpa") return animated_triangle(lex, t);
        if (c == "i") return include(lex, t, path);
        if (c == "xs") return static_transform(lex, t);
        if (c == "x") return animated_transform(lex, t);
        if (c == "k") return animation(lex, t);
        if (c == "a") return animation_params(lex);
        if (c == "d") return void(detail_level_ = count(lex, c));
        if (c == "}") {
            if (open_.empty()) lex.fail(t.line, "'}' without an open transform block");
            open_.pop_back();
            return;
        }
        if (to_float(c)) lex.fail(t.line, cat("expected a command, found the number '", c, "'"));
        lex.fail(t.line, cat("unknown command '", c, "'"));
    }

    void view(Lexer& lex) {
        View v;
        keyword(lex, "from", "v");
        v.from = vec3(lex, "from");
        keyword(lex, "at", "v");
        v.at = vec3(lex, "at");
        keyword(lex, "up", "v");
        v.up = vec3(lex, "up");
        keyword(lex, "angle", "v");
        v.angle_deg = number(lex, "angle");
        keyword(lex, "hither", "v");
        v.hither = number(lex, "hither");
        // BART's parser replaces a hither below 0.0001 by 1 (parse.c, parseViewpoint).
        if (v.hither < 0.0001f) v.hither = 1.0f;
        keyword(lex, "resolution", "v");
        v.width = count(lex, "resolution", 1);
        v.height = count(lex, "resolution", 1);
        model_.view = v;
    }

    // `l x y z [r g b]`, or `la name x y z [r g b]` for a light animated by `k name`.
    void light(Lexer& lex, std::string_view c) {
        Light l;
        l.node = open_.empty() ? 0 : open_.back();
        l.where = {lex.file(), lex.last_line()};
        if (c == "la") l.animation = word(lex, "a light name", c);
        l.position = vec3(lex, "l");
        if (is_number(lex.peek())) l.color = vec3(lex, "l");
        model_.lights.push_back(std::move(l));
    }

    void material(Lexer& lex, std::string_view c) {
        Material m;
        if (c == "f") {
            const Vec3 color = vec3(lex, c);
            const float kd = number(lex, c), ks = number(lex, c);
            for (int i = 0; i < 3; ++i) {
                m.diffuse[i] = color[i] * kd;
                m.specular[i] = color[i] * ks;
            }
        } else {
            m.ambient = vec3(lex, c);
            m.diffuse = vec3(lex, c);
            m.specular = vec3(lex, c);
        }
        m.shine = number(lex, c);
        m.transmittance = number(lex, c);
        m.ior = number(lex, c);
        model_.materials.push_back(m);
    }

    void polygon(Lexer& lex, const Token& t) {
        auto p = placed<Polygon>(lex, t.line);
        const bool normals = t.text == "pp";
        const int n = count(lex, t.text, 3);
        for (int i = 0; i < n; ++i) {
            p.vertices.push_back(vec3(lex, t.text));
            if (normals) p.normals.push_back(vec3(lex, t.text));
        }
        model_.polygons.push_back(std::move(p));
    }

    // `tt tex` (x y z u v per vertex) or the patch `ttp tex` (x y z nx ny nz u v).
    void textured_triangle(Lexer& lex, const Token& t) {
        auto p = placed<Polygon>(lex, t.line);
        const bool normals = t.text == "ttp";
        p.texture = optional_word(lex);
        for (int i = 0; i < 3; ++i) {
            p.vertices.push_back(vec3(lex, t.text));
            if (normals) p.normals.push_back(vec3(lex, t.text));
            p.uvs.push_back(vec2(lex, t.text));
        }
        model_.polygons.push_back(std::move(p));
    }

    void sphere(Lexer& lex, const Token& t) {
        auto s = placed<Sphere>(lex, t.line);
        s.center = vec3(lex, t.text);
        s.radius = number(lex, t.text);
        model_.spheres.push_back(std::move(s));
    }

    void cone(Lexer& lex, const Token& t) {
        auto k = placed<Cone>(lex, t.line);
        k.base = vec3(lex, t.text);
        k.base_radius = number(lex, t.text);
        k.apex = vec3(lex, t.text);
        k.apex_radius = number(lex, t.text);
        model_.cones.push_back(std::move(k));
    }

    void mesh(Lexer& lex, const Token& t) {
        auto m = placed<Mesh>(lex, t.line);
        bool have_vertices = false, have_normals = false, have_uvs = false;
        for (;;) {
            const Token sub = need(lex, "'vertices', 'normals', 'texturecoords' or 'triangles' in mesh 'm'");
            if (sub.text == "vertices") {
                // Counts are read, not trusted: items are appended as they come, so a huge
                // count in a short file ends in "unexpected end of file", not in an allocation.
                const int n = count(lex, sub.text);
                for (int i = 0; i < n; ++i) m.vertices.push_back(vec3(lex, sub.text));
                have_vertices = true;
            } else if (sub.text == "normals") {
                const int n = count(lex, sub.text);
                for (int i = 0; i < n; ++i) m.normals.push_back(vec3(lex, sub.text));
                have_normals = true;
            } else if (sub.text == "texturecoords") {
                const int n = count(lex, sub.text);
                m.texture = optional_word(lex);
                for (int i = 0; i < n; ++i) m.uvs.push_back(vec2(lex, sub.text));
                have_uvs = true;
            } else if (sub.text == "triangles") {
                if (!have_vertices) lex.fail(sub.line, "mesh 'm' has 'triangles' before 'vertices'");
                const int n = count(lex, sub.text);
                for (int i = 0; i < n; ++i) {
                    m.vertex_indices.push_back(indices(lex, m.vertices.size(), "vertex"));
                    if (have_normals) m.normal_indices.push_back(indices(lex, m.normals.size(), "normal"));
                    if (have_uvs) m.uv_indices.push_back(indices(lex, m.uvs.size(), "texture coordinate"));
                }
                model_.meshes.push_back(std::move(m));
                return;  // `triangles` ends the mesh block
            } else {
                lex.fail(sub.line, cat("mesh 'm' expects 'vertices', 'normals', 'texturecoords' or 'triangles', found '", sub.text, "'"));
            }
        }
    }

    std::array<std::uint32_t, 3> indices(Lexer& lex, std::size_t size, std::string_view what) {
        std::array<std::uint32_t, 3> tri{};
        for (std::uint32_t& i : tri) {
            const int v = count(lex, "triangles");
            if (static_cast<std::size_t>(v) >= size)
                lex.fail(lex.last_line(), cat("triangles: ", what, " index ", v, " out of range (the mesh has ", size, ")"));
            i = static_cast<std::uint32_t>(v);
        }
        return tri;
    }

    void animated_triangle(Lexer& lex, const Token& t) {
        auto a = placed<AnimatedTriangle>(lex, t.line);
        const int n = count(lex, t.text, 1);
        for (int i = 0; i < n; ++i) {
            TriangleKey& k = a.keys.emplace_back();
            k.time = number(lex, t.text);
            for (int v = 0; v < 3; ++v) {
                k.positions[v] = vec3(lex, t.text);
                k.normals[v] = vec3(lex, t.text);
            }
        }
        model_.animated_triangles.push_back(std::move(a));
    }

    void include(Lexer& lex, const Token& t, const std::filesystem::path& path) {
        // `i detail file`: BART skips the file when its detail level exceeds the one `d` set
        // (0 unless set); a missing level is taken as 0.
        int detail = 0;
        if (is_number(lex.peek())) detail = count(lex, "i");
        const Token name = need(lex, "a file name for 'i'");
        if (detail > detail_level_) return;
        const std::filesystem::path target = (path.parent_path() / std::string(name.text)).lexically_normal();
        for (const std::filesystem::path& a : active_)
            if (a == target) lex.fail(name.line, cat("include cycle: '", target.string(), "' includes itself"));
        parse_file(target, cat(lex.file(), ":", t.line, ": "));
    }

    void static_transform(Lexer& lex, const Token& t) {
        TransformNode n;
        n.kind = TransformNode::Kind::fixed;
        n.scale = vec3(lex, t.text);
        n.rotation_axis = vec3(lex, t.text);
        n.rotation_deg = number(lex, t.text);
        n.translation = vec3(lex, t.text);
        open_brace(lex, t.text);
        push_node(std::move(n), lex, t.line);
    }

    void animated_transform(Lexer& lex, const Token& t) {
        TransformNode n;
        n.kind = TransformNode::Kind::animated;
        n.animation = word(lex, "an animation name", t.text);
        open_brace(lex, t.text);
        push_node(std::move(n), lex, t.line);
    }

    void push_node(TransformNode n, const Lexer& lex, int line) {
        n.parent = open_.empty() ? 0 : open_.back();
        n.where = {lex.file(), line};
        model_.nodes.push_back(std::move(n));
        open_.push_back(static_cast<int>(model_.nodes.size()) - 1);
    }

    void animation(Lexer& lex, const Token& t) {
        Animation a;
        a.name = word(lex, "an animation name", t.text);
        a.where = {lex.file(), t.line};
        open_brace(lex, t.text);
        for (;;) {
            const Token track = need(lex, cat("'transl', 'rot', 'scale' or '}' in 'k ", a.name, "'"));
            if (track.text == "}") break;
            if (track.text == "transl" || track.text == "scale") {
                auto& keys = track.text == "transl" ? a.translations : a.scales;
                const int n = count(lex, track.text, 1);
                for (int i = 0; i < n; ++i) {
                    VectorKey k;
                    k.time = number(lex, track.text);
                    k.value = vec3(lex, track.text);
                    k.tension = number(lex, track.text);
                    k.continuity = number(lex, track.text);
                    k.bias = number(lex, track.text);
                    keys.push_back(k);
                }
            } else if (track.text == "rot") {
                const int n = count(lex, track.text, 1);
                for (int i = 0; i < n; ++i) {
                    RotationKey k;
                    k.time = number(lex, track.text);
                    k.axis = vec3(lex, track.text);
                    k.angle_deg = number(lex, track.text);
                    k.tension = number(lex, track.text);
                    k.continuity = number(lex, track.text);
                    k.bias = number(lex, track.text);
                    a.rotations.push_back(k);
                }
            } else if (track.text == "visibility") {
                lex.fail(track.line, cat("'k ", a.name, "': visibility keys are not supported (none of "
                                         "the BART scenes uses them)"));
            } else {
                lex.fail(track.line, cat("'k ", a.name, "' expects 'transl', 'rot', 'scale' or '}', found '", track.text, "'"));
            }
        }
        model_.animations.push_back(std::move(a));
    }

    void animation_params(Lexer& lex) {
        AnimationParams p;
        p.start_time = number(lex, "a");
        p.end_time = number(lex, "a");
        p.frame_count = count(lex, "a", 1);
        model_.animation_params = p;
    }

    AffModel& model_;
    int detail_level_ = 0;  // `d`: includes with a higher level are skipped
    std::vector<int> open_;  // the transform nodes whose '{' is open, innermost last
    std::vector<std::filesystem::path> active_;  // the include chain being read
};

}  // namespace

AffModel parse_aff_file(const std::filesystem::path& path) {
    AffModel model;
    Parser parser(model);
    parser.parse_file(path, "");
    parser.finish();
    return model;
}

AffModel parse_aff_text(std::string_view text, const std::filesystem::path& name) {
    AffModel model;
    Parser parser(model);
    parser.parse_text(text, name);
    parser.finish();
    return model;
}

}  // namespace dynrt::aff
