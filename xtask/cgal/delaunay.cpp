// delaunay.cpp -- CGAL reference driver for delmesh validation and benchmarks.
//
// Usage: delaunay IN.node OUT.cells
//
// Reads a TetGen/Triangle `.node` file, builds the Delaunay triangulation of the
// dimension given in its header (2 or 3) with CGAL (EPICK kernel,
// Delaunay_triangulation_2/3, range insertion of (point, input index) pairs, which
// spatially sorts the points first), and writes every finite cell as one line of
// 0-based input indices (sorted ascending within the line, lines sorted
// lexicographically). This is the `.cells` format shared by all of xtask's
// reference and comparison code.
//
// Only the construction (the single range `insert` call) is timed, with
// std::chrono::steady_clock (wall) and CLOCK_PROCESS_CPUTIME_ID (CPU; TetGen's own
// timings are CPU time from clock(), so this is the like-for-like number on a
// loaded machine). Peak memory is the process's peak resident set size taken right
// after construction (so it includes the input (point, index) pairs and the earlier
// parsing, but not the output phase): VmHWM from /proc/self/status, because
// getrusage's ru_maxrss survives exec and would report the spawning parent's peak if
// that was larger (see peak_rss_kb).
// Stdout carries exactly these four lines, parsed by xtask/src/reference.rs:
//
//   cgal_build_seconds <wall secs>
//   cgal_build_cpu_seconds <cpu secs>
//   cgal_cells <n>
//   cgal_peak_rss_kb <kb>
//
// Diagnostics (merged duplicates, degenerate input) go to stderr.
//
// Duplicate points: CGAL keeps one vertex per distinct position and silently drops
// the others; which input index survives depends on the (spatially sorted)
// insertion order. The cells are written with the index CGAL kept, so on inputs
// with duplicates the raw `.cells` files of two tools are not comparable: the
// duplicates are not compared here. (xtask maps every index to the smallest index
// of its coincident group before comparing, see xtask/src/formats.rs.)
//
// Build (done by `cargo xtask`, see xtask/src/reference.rs):
//   g++ -O3 -DNDEBUG -std=c++17 -frounding-math -o cgal-delaunay delaunay.cpp -lmpfr -lgmp
// (-frounding-math is what CGAL's own CMake setup adds for GCC; interval filters need it.)

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_data_structure_2.h>
#include <CGAL/Triangulation_data_structure_3.h>
#include <CGAL/Triangulation_face_base_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Index = std::uint32_t;

using Vb3 = CGAL::Triangulation_vertex_base_with_info_3<Index, K>;
using Cb3 = CGAL::Delaunay_triangulation_cell_base_3<K>;
using Tds3 = CGAL::Triangulation_data_structure_3<Vb3, Cb3>;
using Dt3 = CGAL::Delaunay_triangulation_3<K, Tds3>;

using Vb2 = CGAL::Triangulation_vertex_base_with_info_2<Index, K>;
using Fb2 = CGAL::Triangulation_face_base_2<K>;
using Tds2 = CGAL::Triangulation_data_structure_2<Vb2, Fb2>;
using Dt2 = CGAL::Delaunay_triangulation_2<K, Tds2>;

[[noreturn]] void die(const std::string& msg) {
    std::fprintf(stderr, "cgal-delaunay: %s\n", msg.c_str());
    std::exit(1);
}

// Parsed `.node` file: coordinates are stored flat, `dim` per point.
struct NodeFile {
    int dim = 0;
    long long first_index = 0;
    std::vector<double> coords;
    std::size_t count() const { return dim == 0 ? 0 : coords.size() / dim; }
};

std::string read_file(const char* path) {
    std::FILE* f = std::fopen(path, "rb");
    if (!f) die(std::string("cannot open ") + path);
    std::string data;
    char buf[1 << 16];
    std::size_t got;
    while ((got = std::fread(buf, 1, sizeof buf, f)) > 0) data.append(buf, got);
    std::fclose(f);
    return data;
}

// Splits one line (comment already cut off) into whitespace-separated tokens.
void tokenize(const char* begin, const char* end, std::vector<std::string>& out) {
    out.clear();
    const char* p = begin;
    while (p < end) {
        while (p < end && (*p == ' ' || *p == '\t' || *p == '\r' || *p == ',')) ++p;
        const char* q = p;
        while (q < end && !(*q == ' ' || *q == '\t' || *q == '\r' || *q == ',')) ++q;
        if (q > p) out.emplace_back(p, q);
        p = q;
    }
}

double parse_double(const std::string& s, std::size_t line_no) {
    char* endp = nullptr;
    double v = std::strtod(s.c_str(), &endp);
    if (endp == s.c_str() || *endp != '\0')
        die("line " + std::to_string(line_no) + ": bad number '" + s + "'");
    return v;
}

long long parse_int(const std::string& s, std::size_t line_no) {
    char* endp = nullptr;
    long long v = std::strtoll(s.c_str(), &endp, 10);
    if (endp == s.c_str() || *endp != '\0')
        die("line " + std::to_string(line_no) + ": bad integer '" + s + "'");
    return v;
}

// `.node` format (TetGen and Triangle): first non-comment line is
// `<n> <dim> <nattr> <nmarkers>`, then n lines `<idx> x y [z] [attrs...] [marker]`.
// `#` starts a comment anywhere on a line. Indices must be consecutive from the first
// one (0 or 1).
NodeFile parse_node(const char* path) {
    const std::string data = read_file(path);
    NodeFile nf;
    std::vector<std::string> tok;
    long long n = -1;
    std::size_t line_no = 0;
    std::size_t pos = 0;
    while (pos < data.size()) {
        std::size_t eol = data.find('\n', pos);
        if (eol == std::string::npos) eol = data.size();
        ++line_no;
        const char* line = data.data() + pos;
        const void* hash = std::memchr(line, '#', eol - pos);
        const char* stop = hash ? static_cast<const char*>(hash) : data.data() + eol;
        tokenize(line, stop, tok);
        pos = eol + 1;
        if (tok.empty()) continue;
        if (n < 0) {
            n = parse_int(tok[0], line_no);
            nf.dim = tok.size() > 1 ? static_cast<int>(parse_int(tok[1], line_no)) : 3;
            if (n <= 0) die("header declares no points");
            if (nf.dim != 2 && nf.dim != 3) die("dimension must be 2 or 3");
            if (n > static_cast<long long>(UINT32_MAX)) die("too many points");
            nf.coords.reserve(static_cast<std::size_t>(n) * nf.dim);
            continue;
        }
        if (static_cast<long long>(nf.count()) == n) break;  // trailing content ignored
        if (static_cast<int>(tok.size()) < 1 + nf.dim)
            die("line " + std::to_string(line_no) + ": too few fields");
        const long long idx = parse_int(tok[0], line_no);
        if (nf.coords.empty()) nf.first_index = idx;
        if (idx != nf.first_index + static_cast<long long>(nf.count()))
            die("line " + std::to_string(line_no) + ": indices are not consecutive");
        for (int d = 0; d < nf.dim; ++d) nf.coords.push_back(parse_double(tok[1 + d], line_no));
    }
    if (n < 0) die("no header");
    if (static_cast<long long>(nf.count()) != n)
        die("header declares " + std::to_string(n) + " points, file has " +
            std::to_string(nf.count()));
    return nf;
}

// Peak resident memory of this process in KiB.
//
// getrusage(RUSAGE_SELF).ru_maxrss is *preserved across execve* on Linux, so a driver
// spawned by a parent that once had a large RSS (xtask itself, after reading a big
// `.cells` file) would report the parent's peak. The high-water mark of the current
// address space, `VmHWM` in /proc/self/status, starts afresh at exec, so it is used
// when available, with ru_maxrss as the fallback.
long peak_rss_kb() {
    if (std::FILE* f = std::fopen("/proc/self/status", "r")) {
        char line[256];
        long kb = -1;
        while (std::fgets(line, sizeof line, f))
            if (std::strncmp(line, "VmHWM:", 6) == 0) kb = std::strtol(line + 6, nullptr, 10);
        std::fclose(f);
        if (kb >= 0) return kb;
    }
    struct rusage ru;
    std::memset(&ru, 0, sizeof ru);
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_maxrss;  // kilobytes on Linux
}

template <std::size_t N>
void write_cells(const char* path, std::vector<std::array<Index, N>>& cells) {
    for (auto& c : cells) std::sort(c.begin(), c.end());
    std::sort(cells.begin(), cells.end());
    std::FILE* f = std::fopen(path, "wb");
    if (!f) die(std::string("cannot create ") + path);
    std::vector<char> buf;
    buf.reserve(1 << 20);
    char num[16];
    for (const auto& c : cells) {
        for (std::size_t i = 0; i < N; ++i) {
            auto res = std::to_chars(num, num + sizeof num, c[i]);
            buf.insert(buf.end(), num, res.ptr);
            buf.push_back(i + 1 == N ? '\n' : ' ');
        }
        if (buf.size() > (1 << 20) - 64) {
            std::fwrite(buf.data(), 1, buf.size(), f);
            buf.clear();
        }
    }
    std::fwrite(buf.data(), 1, buf.size(), f);
    if (std::fclose(f) != 0) die(std::string("error writing ") + path);
}

// CPU time of this process (all threads; the construction is single-threaded).
double cpu_seconds() {
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

struct Result {
    double seconds;
    double cpu_seconds;
    std::size_t cells;
    long rss_kb;
};

Result run3(NodeFile nf, const char* out_path) {
    const std::size_t n = nf.count();
    std::vector<std::pair<Dt3::Point, Index>> pts;
    pts.reserve(n);
    for (std::size_t i = 0; i < n; ++i)
        pts.emplace_back(Dt3::Point(nf.coords[3 * i], nf.coords[3 * i + 1], nf.coords[3 * i + 2]),
                         static_cast<Index>(i));
    std::vector<double>().swap(nf.coords);  // only `pts` stays alive during construction

    Dt3 dt;
    const double c0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    dt.insert(pts.begin(), pts.end());
    const auto t1 = std::chrono::steady_clock::now();
    const double c1 = cpu_seconds();
    const long rss = peak_rss_kb();

    if (dt.number_of_vertices() != n)
        std::fprintf(stderr, "cgal-delaunay: %zu of %zu points kept (duplicates merged)\n",
                     static_cast<std::size_t>(dt.number_of_vertices()), n);
    if (dt.dimension() < 3)
        std::fprintf(stderr, "cgal-delaunay: input is degenerate (affine dimension %d)\n",
                     dt.dimension());

    std::vector<std::array<Index, 4>> cells;
    cells.reserve(dt.number_of_finite_cells());
    for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c)
        cells.push_back({c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(),
                         c->vertex(3)->info()});
    write_cells(out_path, cells);
    return {std::chrono::duration<double>(t1 - t0).count(), c1 - c0, cells.size(), rss};
}

Result run2(NodeFile nf, const char* out_path) {
    const std::size_t n = nf.count();
    std::vector<std::pair<Dt2::Point, Index>> pts;
    pts.reserve(n);
    for (std::size_t i = 0; i < n; ++i)
        pts.emplace_back(Dt2::Point(nf.coords[2 * i], nf.coords[2 * i + 1]),
                         static_cast<Index>(i));
    std::vector<double>().swap(nf.coords);  // only `pts` stays alive during construction

    Dt2 dt;
    const double c0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    dt.insert(pts.begin(), pts.end());
    const auto t1 = std::chrono::steady_clock::now();
    const double c1 = cpu_seconds();
    const long rss = peak_rss_kb();

    if (dt.number_of_vertices() != n)
        std::fprintf(stderr, "cgal-delaunay: %zu of %zu points kept (duplicates merged)\n",
                     static_cast<std::size_t>(dt.number_of_vertices()), n);
    if (dt.dimension() < 2)
        std::fprintf(stderr, "cgal-delaunay: input is degenerate (affine dimension %d)\n",
                     dt.dimension());

    std::vector<std::array<Index, 3>> cells;
    cells.reserve(dt.number_of_faces());
    for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f)
        cells.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
    write_cells(out_path, cells);
    return {std::chrono::duration<double>(t1 - t0).count(), c1 - c0, cells.size(), rss};
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s IN.node OUT.cells\n", argv[0]);
        return 2;
    }
    NodeFile nf = parse_node(argv[1]);
    // The `.node` indices are used 0-based from here on: input index i is point i.
    const int dim = nf.dim;
    const Result r = dim == 3 ? run3(std::move(nf), argv[2]) : run2(std::move(nf), argv[2]);
    std::printf("cgal_build_seconds %.6f\n", r.seconds);
    std::printf("cgal_build_cpu_seconds %.6f\n", r.cpu_seconds);
    std::printf("cgal_cells %zu\n", r.cells);
    std::printf("cgal_peak_rss_kb %ld\n", r.rss_kb);
    return 0;
}
