// cdt2.cpp -- CGAL reference driver for delmesh's 2D constrained Delaunay triangulation.
//
// Usage: cdt2 IN.poly OUT.cells
//
// Reads a 0-based Triangle `.poly` file as `cargo xtask cdt` writes it (points without
// attributes or markers, segments with a marker, no holes: the domain is given by the nesting
// of the closed loops), builds CGAL's Constrained_Delaunay_triangulation_2 (EPICK kernel,
// exact predicates, no intersecting constraints) by a range insertion of (point, index) pairs
// followed by one insert_constraint per segment, marks the domain by nesting (faces reached
// from the infinite face without crossing a constraint are outside; each constraint crossed
// flips inside/outside), and writes every domain face as one line of 0-based input indices,
// sorted within the line, lines sorted: the `.cells` format of xtask.
//
// Stdout: `cgal_build_seconds <wall secs>` (points, constraints and marking) and
// `cgal_cells <n>`.

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Index = std::uint32_t;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<Index, K>;
using Fbi = CGAL::Triangulation_face_base_with_info_2<int, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbi>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;

[[noreturn]] void die(const std::string& msg) {
    std::fprintf(stderr, "cgal-cdt2: %s\n", msg.c_str());
    std::exit(1);
}

// The next line with data (comments after '#' removed), split into tokens.
bool next_tokens(std::istream& in, std::vector<std::string>& tok) {
    std::string line;
    while (std::getline(in, line)) {
        auto hash = line.find('#');
        if (hash != std::string::npos) line.resize(hash);
        std::istringstream ss(line);
        tok.clear();
        std::string t;
        while (ss >> t) tok.push_back(t);
        if (!tok.empty()) return true;
    }
    return false;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) die("usage: cdt2 IN.poly OUT.cells");
    std::ifstream in(argv[1]);
    if (!in) die(std::string("cannot open ") + argv[1]);
    std::vector<std::string> tok;
    if (!next_tokens(in, tok)) die("no header");
    const long n = std::stol(tok[0]);
    std::vector<std::pair<K::Point_2, Index>> pts;
    pts.reserve(n);
    for (long i = 0; i < n; ++i) {
        if (!next_tokens(in, tok) || tok.size() < 3) die("bad point line");
        pts.emplace_back(K::Point_2(std::strtod(tok[1].c_str(), nullptr),
                                    std::strtod(tok[2].c_str(), nullptr)),
                         static_cast<Index>(i));
    }
    if (!next_tokens(in, tok)) die("no segment header");
    const long m = std::stol(tok[0]);
    std::vector<std::array<Index, 2>> segs(m);
    for (long i = 0; i < m; ++i) {
        if (!next_tokens(in, tok) || tok.size() < 3) die("bad segment line");
        segs[i] = {static_cast<Index>(std::stol(tok[1])), static_cast<Index>(std::stol(tok[2]))};
    }

    const auto t0 = std::chrono::steady_clock::now();
    Cdt cdt;
    cdt.insert(pts.begin(), pts.end());
    std::vector<Cdt::Vertex_handle> handle(n);
    for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
        handle[v->info()] = v;
    for (const auto& s : segs) cdt.insert_constraint(handle[s[0]], handle[s[1]]);
    // Nesting levels by breadth-first search: level 0 outside, +1 across each constraint.
    for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
    std::deque<Cdt::Face_handle> border;
    border.push_back(cdt.infinite_face());
    int level = 0;
    while (!border.empty()) {
        std::deque<Cdt::Face_handle> next_border;
        std::deque<Cdt::Face_handle> queue;
        for (auto f : border)
            if (f->info() == -1) {
                f->info() = level;
                queue.push_back(f);
            }
        while (!queue.empty()) {
            auto f = queue.front();
            queue.pop_front();
            for (int i = 0; i < 3; ++i) {
                auto g = f->neighbor(i);
                if (g->info() != -1) continue;
                if (cdt.is_constrained(Cdt::Edge(f, i))) {
                    next_border.push_back(g);
                } else {
                    g->info() = level;
                    queue.push_back(g);
                }
            }
        }
        border.swap(next_border);
        ++level;
    }
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    std::vector<std::array<Index, 3>> cells;
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
        if (f->info() % 2 != 1) continue;
        std::array<Index, 3> c = {f->vertex(0)->info(), f->vertex(1)->info(),
                                  f->vertex(2)->info()};
        std::sort(c.begin(), c.end());
        cells.push_back(c);
    }
    std::sort(cells.begin(), cells.end());
    std::FILE* out = std::fopen(argv[2], "w");
    if (!out) die(std::string("cannot write ") + argv[2]);
    for (const auto& c : cells) std::fprintf(out, "%u %u %u\n", c[0], c[1], c[2]);
    std::fclose(out);
    std::printf("cgal_build_seconds %.6f\ncgal_cells %zu\n", secs, cells.size());
    return 0;
}
