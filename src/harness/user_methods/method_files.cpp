// Method files: the run-time method registry — a parsed method's storage and its MethodInfo row,
// loading files and folders, and the coefficient checks of loaded methods (method_files.hpp,
// docs/method-files.md). The reader and parser are method_file_reader.hpp and
// method_file_parse.cpp.
#include "harness/user_methods/method_files.hpp"

#include "harness/json_file.hpp"
#include "harness/user_methods/method_file_reader.hpp"

#include <algorithm>
#include <array>
#include <deque>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <utility>

namespace dampsym {
namespace method_file {
namespace {

struct LoadedErk {
    ExponentialRKData data;
    ExpTableauFns fns;
};
struct LoadedPerk {
    PartitionedExponentialRKData data;
    ExpTableauFns q, p;
};

struct Registry {
    std::deque<std::string> strings;
    std::deque<ButcherTableau> tableaux;
    std::deque<LoadedErk> erks;
    std::deque<LoadedPerk> perks;
    std::deque<GlmCoefficients> glms;
    std::deque<MethodInfo> rows;
    std::map<std::string, std::string, std::less<>> file_of;      // id -> file
    std::map<std::string, std::vector<std::string>> loaded_files; // canonical path -> ids
};

Registry& registry() {
    static Registry r;
    return r;
}

std::string_view keep(std::string s) {
    return registry().strings.emplace_back(std::move(s));
}

// ERK coefficient function of a loaded row: the data is found by its address.
void loaded_erk_coefficients(const ExponentialRKData& self, double x, ExponentialTableau& out) {
    for (const LoadedErk& e : registry().erks)
        if (&e.data == &self) return e.fns.eval(x, out);
}

// PERK coefficient functions take no data argument (exponential_tableaux.hpp), so each loaded
// PERK row gets one of max_perk_methods fixed functions, slot K evaluating the K-th loaded row.
template <std::size_t K>
void perk_slot(double x_B, ExponentialTableau& q, ExponentialTableau& p) {
    const LoadedPerk& m = registry().perks[K];
    m.q.eval(x_B, q);
    m.p.eval(x_B, p);
}
using PerkFn = void (*)(double, ExponentialTableau&, ExponentialTableau&);
template <std::size_t... K>
constexpr std::array<PerkFn, sizeof...(K)> make_perk_slots(std::index_sequence<K...>) {
    return {&perk_slot<K>...};
}
constexpr auto perk_slots = make_perk_slots(std::make_index_sequence<max_perk_methods>{});

// Registers a parsed method (storage first, then the row pointing into it).
void commit(Parsed& m, const std::string& file) {
    Registry& reg = registry();
    const std::string_view id = keep(m.id);
    const std::string_view citation = keep(m.citation);
    MethodData data = RungeKuttaTableau{nullptr};
    if (m.family == "rk") {
        const ButcherTableau* t = &reg.tableaux.emplace_back(std::move(*m.t1));
        if (m.integrating_factor)
            data = IntegratingFactorTableau{t};
        else
            data = RungeKuttaTableau{t};
    } else if (m.family == "partitioned-rk") {
        const ButcherTableau* q = &reg.tableaux.emplace_back(std::move(*m.t1));
        const ButcherTableau* p = &reg.tableaux.emplace_back(std::move(*m.t2));
        data = PartitionedTableau{q, p};
    } else if (m.family == "exponential-rk") {
        LoadedErk& e = reg.erks.emplace_back();
        e.fns = std::move(*m.e1);
        e.data = ExponentialRKData{id, citation, "file", e.fns.s, nullptr, loaded_erk_coefficients};
        data = ExponentialCoefficients{&e.data};
    } else if (m.family == "partitioned-exponential-rk") {
        const std::size_t slot = reg.perks.size();
        LoadedPerk& e = reg.perks.emplace_back();
        e.q = std::move(*m.e1);
        e.p = std::move(*m.e2);
        e.data = PartitionedExponentialRKData{id, citation, "file", e.q.s, perk_slots[slot]};
        data = PartitionedExponentialCoefficients{&e.data};
    } else if (m.family == "general-linear") {
        GlmCoefficients& g = reg.glms.emplace_back(std::move(*m.glm));
        g.name = id;
        g.citation = citation;
        data = GeneralLinearCoefficients{&g};
    } else { // the reader refuses any other family (method_file_parse.cpp file_families)
        throw std::logic_error("method file: no registration for family '" + m.family + "'");
    }
    reg.rows.push_back(MethodInfo{id, m.order, m.implicit, m.form, m.claims, citation, data});
    reg.file_of.emplace(m.id, file);
}

} // namespace

std::size_t loaded_perk_count() {
    return registry().perks.size();
}

std::string file_defining(std::string_view id) {
    const auto it = registry().file_of.find(id);
    return it == registry().file_of.end() ? std::string() : it->second;
}

} // namespace method_file

namespace {
namespace fs = std::filesystem;
using json = nlohmann::json;
} // namespace

const MethodInfo* find_loaded_method(std::string_view id) {
    for (const MethodInfo& m : method_file::registry().rows)
        if (m.id == id) return &m;
    return nullptr;
}

const MethodInfo* register_runtime_method(const MethodInfo& row, const std::string& source) {
    method_file::Registry& reg = method_file::registry();
    MethodInfo m = row;
    m.id = method_file::keep(std::string(row.id));
    m.citation = method_file::keep(std::string(row.citation));
    reg.rows.push_back(m);
    reg.file_of.emplace(std::string(m.id), source);
    return &reg.rows.back();
}

std::string loaded_method_source(std::string_view id) {
    return method_file::file_defining(id);
}

std::vector<const MethodInfo*> loaded_methods() {
    std::vector<const MethodInfo*> out;
    for (const MethodInfo& m : method_file::registry().rows) out.push_back(&m);
    return out;
}

std::vector<const MethodInfo*> load_method_file(const std::string& path) {
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(path, ec);
    const std::string key = ec ? path : canonical.string();
    method_file::Registry& reg = method_file::registry();
    if (!reg.loaded_files.count(key)) {
        const json j = read_json_file(path, "method file"); // regular, bounded, depth, duplicates
        method_file::Reader r(path);
        std::vector<method_file::Parsed> parsed;
        parsed.push_back(
            method_file::parse_method(j, r)); // every method validated before any is registered
        std::vector<std::string> ids;
        for (auto& m : parsed) {
            ids.push_back(m.id);
            method_file::commit(m, fs::path(path).lexically_normal().string());
        }
        reg.loaded_files[key] = std::move(ids);
    }
    std::vector<const MethodInfo*> out;
    for (const auto& id : reg.loaded_files[key]) out.push_back(find_loaded_method(id));
    return out;
}

std::string check_method_text(const std::string& text, const std::string& file) {
    const json j = parse_json_checked(text, file); // as read_case_json after reading the file
    method_file::Reader r(file);
    return method_file::parse_method(j, r).id;
}

std::vector<const MethodInfo*> load_method_text(const std::string& text,
                                                const std::string& source) {
    const json j = parse_json_checked(text, source); // as a file's text (check_method_text)
    method_file::Reader r(source);
    method_file::Parsed m = method_file::parse_method(j, r);
    const std::string id = m.id;
    method_file::commit(m, source);
    return {find_loaded_method(id)};
}

void load_method_folder(const std::string& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return;
    std::vector<std::string> paths;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ".json") paths.push_back(e.path().string());
    std::sort(paths.begin(), paths.end());
    for (const auto& p : paths) load_method_file(p);
}

std::string method_file_of(std::string_view id) {
    const auto it = method_file::registry().file_of.find(id);
    return it == method_file::registry().file_of.end() ? std::string() : it->second;
}

std::string method_folder_beside(const std::string& cases_dir) {
    fs::path p(cases_dir);
    if (!p.has_filename()) p = p.parent_path(); // "verify/cases/"
    return (p.parent_path() / "methods").string();
}

} // namespace dampsym
