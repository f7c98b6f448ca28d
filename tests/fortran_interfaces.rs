//! `include/meshmove.f90` against `include/meshmove.h`, mechanically: every C function has a
//! `bind(c)` interface of the same name with the same number of arguments, each of a compatible
//! type and passing (by value or by reference), and is called by the high-level module
//! `meshmove`; every function returning a status is marked `MESHMOVE_MUST_USE`; every `bind(c)`
//! type has the fields of its C struct in order; every named constant of the header has a Fortran
//! parameter of the same value.

use std::collections::BTreeMap;
use std::path::Path;

fn read(rel: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)).unwrap()
}

/// Removes `/* */` and `//` comments and preprocessor lines.
fn c_code(h: &str) -> String {
    let mut out = String::new();
    let mut rest = h;
    while let Some(i) = rest.find("/*") {
        out.push_str(&rest[..i]);
        rest = rest[i..].find("*/").map_or("", |j| &rest[i + j + 2..]);
    }
    out.push_str(rest);
    out.lines()
        .filter(|l| !l.trim_start().starts_with('#'))
        .map(|l| l.find("//").map_or(l, |i| &l[..i]))
        .collect::<Vec<_>>()
        .join("\n")
}

/// A C type as the check sees it: base name (`const`, `struct` dropped) and pointer depth.
#[derive(Debug, Clone, PartialEq)]
struct CType {
    base: String,
    ptr: usize,
}

/// The attribute macro in front of status-returning functions.
const MUST_USE: &str = "MESHMOVE_MUST_USE";

fn c_type(decl: &str) -> CType {
    let ptr = decl.matches('*').count();
    let words: Vec<&str> = decl
        .split(|c: char| c.is_whitespace() || c == '*')
        .filter(|w| !w.is_empty() && *w != "const" && *w != "struct" && *w != MUST_USE)
        .collect();
    CType { base: words.first().copied().unwrap_or("void").to_string(), ptr }
}

/// A function of the header: its return type, parameter types, and whether it is marked
/// `MESHMOVE_MUST_USE`.
struct CFunction {
    ret: CType,
    params: Vec<CType>,
    must_use: bool,
}

/// Every `meshmove_*` function of the header by name.
fn c_functions(h: &str) -> BTreeMap<String, CFunction> {
    let mut out = BTreeMap::new();
    for stmt in c_code(h).split(';') {
        let stmt = stmt.rsplit(['{', '}']).next().unwrap().trim();
        let (Some(open), Some(close)) = (stmt.find('('), stmt.rfind(')')) else { continue };
        if stmt.starts_with("typedef") || !stmt.ends_with(')') {
            continue;
        }
        let head = &stmt[..open];
        let name_at = head.rfind(|c: char| !(c.is_alphanumeric() || c == '_')).map_or(0, |i| i + 1);
        let name = head[name_at..].to_string();
        if !name.starts_with("meshmove_") {
            continue;
        }
        let params = stmt[open + 1..close].trim();
        let args = if params == "void" || params.is_empty() {
            Vec::new()
        } else {
            params
                .split(',')
                .map(|p| {
                    // drop the parameter name
                    let p = p.trim();
                    let cut = p.rfind(|c: char| !(c.is_alphanumeric() || c == '_')).map_or(0, |i| i + 1);
                    c_type(&p[..cut])
                })
                .collect()
        };
        let ret = head[..name_at].trim();
        let must_use = ret.split_whitespace().any(|w| w == MUST_USE);
        out.insert(name, CFunction { ret: c_type(ret), params: args, must_use });
    }
    out
}

/// The `meshmove_c` module, comments dropped and continuation lines joined.
fn fortran_lines(f: &str) -> Vec<String> {
    let module = &f[f.find("module meshmove_c").unwrap()..f.find("end module meshmove_c").unwrap()];
    let mut lines = Vec::new();
    let mut cur = String::new();
    for l in module.lines() {
        let l = l.find('!').map_or(l, |i| &l[..i]).trim();
        let (body, cont) = match l.strip_suffix('&') {
            Some(b) => (b, true),
            None => (l, false),
        };
        cur.push_str(body.trim_start_matches('&'));
        cur.push(' ');
        if !cont {
            if !cur.trim().is_empty() {
                lines.push(cur.trim().to_string());
            }
            cur.clear();
        }
    }
    lines
}

/// A Fortran dummy argument: its type spec (e.g. `integer(c_int32_t)`) and whether it has VALUE.
#[derive(Debug, Clone)]
struct FArg {
    ty: String,
    value: bool,
}

fn split_decl(l: &str) -> Option<(String, bool, Vec<String>)> {
    let (left, right) = l.split_once("::")?;
    let left = left.to_lowercase().replace(' ', "");
    let ty = left.split(',').next().unwrap().to_string();
    let value = left.split(',').any(|a| a == "value");
    // names, without array specs like (*) or (2, n)
    let mut names = Vec::new();
    let mut depth = 0;
    let mut name = String::new();
    for c in right.chars() {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            ',' if depth == 0 => names.push(std::mem::take(&mut name)),
            _ if depth == 0 && !c.is_whitespace() => name.push(c.to_ascii_lowercase()),
            _ => {}
        }
    }
    names.push(name);
    Some((ty, value, names.into_iter().filter(|n| !n.is_empty()).collect()))
}

/// Every `bind(c)` interface: binding name → (Fortran result type, arguments in order).
fn fortran_interfaces(f: &str) -> BTreeMap<String, (String, Vec<FArg>)> {
    let mut out = BTreeMap::new();
    let lines = fortran_lines(f);
    let mut i = 0;
    while i < lines.len() {
        let l = lines[i].to_lowercase();
        let Some(fpos) = l.find(" function ").filter(|_| l.contains("bind(c")) else {
            i += 1;
            continue;
        };
        let result = l[..fpos].replace(' ', "");
        let rest = &l[fpos + " function ".len()..];
        let name = rest[..rest.find('(').unwrap()].trim().to_string();
        let args: Vec<String> = rest[rest.find('(').unwrap() + 1..rest.find(')').unwrap()]
            .split(',')
            .map(|a| a.trim().to_string())
            .filter(|a| !a.is_empty())
            .collect();
        let bind = &l[l.find("bind(c").unwrap()..];
        let cname = match bind.find("name") {
            Some(n) => {
                let q = &lines[i][lines[i].to_lowercase().find("bind(c").unwrap() + n..];
                q.split('"').nth(1).unwrap().to_string()
            }
            None => name.clone(),
        };
        let mut decl: BTreeMap<String, FArg> = BTreeMap::new();
        i += 1;
        while !lines[i].to_lowercase().starts_with("end function") {
            if let Some((ty, value, names)) = split_decl(&lines[i]) {
                for n in names {
                    decl.insert(n, FArg { ty: ty.clone(), value });
                }
            }
            i += 1;
        }
        let args = args
            .iter()
            .map(|a| decl.get(a).cloned().unwrap_or_else(|| panic!("{cname}: argument `{a}` is not declared")))
            .collect();
        out.insert(cname, (result, args));
    }
    out
}

const STRUCTS: [&str; 3] = ["meshmove_report", "meshmove_quality", "meshmove_step_report"];
const HANDLES: [&str; 4] = ["meshmove_mesh", "meshmove_bcs", "meshmove_options", "meshmove_solver"];

/// Whether a Fortran dummy can receive this C parameter.
fn compatible(c: &CType, f: &FArg) -> bool {
    let scalar = |b: &str| match b {
        "int32_t" | "meshmove_status" => Some("integer(c_int32_t)"),
        "size_t" => Some("integer(c_size_t)"),
        "int64_t" => Some("integer(c_int64_t)"),
        "double" => Some("real(c_double)"),
        "char" => Some("character(kind=c_char)"),
        _ => None,
    };
    let cptr_value = f.ty == "type(c_ptr)" && f.value;
    // Callbacks: a function pointer typedef, passed by value.
    if c.ptr == 0
        && matches!(c.base.as_str(), "meshmove_closest_point" | "meshmove_closest_point_checked" | "meshmove_progress")
    {
        return f.ty == "type(c_funptr)" && f.value;
    }
    match c.ptr {
        0 => f.value && scalar(&c.base) == Some(f.ty.as_str()),
        1 if HANDLES.contains(&c.base.as_str()) => cptr_value,
        1 if STRUCTS.contains(&c.base.as_str()) => cptr_value || (!f.value && f.ty == format!("type({})", c.base)),
        1 => cptr_value || (!f.value && scalar(&c.base) == Some(f.ty.as_str())),
        2 => f.ty == "type(c_ptr)" && !f.value,
        _ => false,
    }
}

#[test]
fn every_c_function_has_a_matching_fortran_interface() {
    let c = c_functions(&read("include/meshmove.h"));
    let f = fortran_interfaces(&read("include/meshmove.f90"));
    assert!(c.len() > 30, "parsed only {} C functions", c.len());
    let mut problems = Vec::new();
    for (name, CFunction { ret, params, must_use }) in &c {
        if (ret.base == "meshmove_status") != *must_use {
            problems.push(format!("{name}: returns {ret:?}; MESHMOVE_MUST_USE: {must_use}"));
        }
        let Some((fret, fargs)) = f.get(name) else {
            problems.push(format!("{name}: no bind(c) interface in meshmove.f90"));
            continue;
        };
        let ret_ok = match (ret.base.as_str(), ret.ptr) {
            ("meshmove_status", 0) => fret == "integer(c_int32_t)",
            (_, 1) => fret == "type(c_ptr)",
            _ => false,
        };
        if !ret_ok {
            problems.push(format!("{name}: returns {ret:?} in C, {fret} in Fortran"));
        }
        if params.len() != fargs.len() {
            problems.push(format!("{name}: {} arguments in C, {} in Fortran", params.len(), fargs.len()));
            continue;
        }
        for (k, (p, a)) in params.iter().zip(fargs).enumerate() {
            if !compatible(p, a) {
                problems.push(format!(
                    "{name}: argument {} is {}{} in C, {}{} in Fortran",
                    k + 1,
                    p.base,
                    "*".repeat(p.ptr),
                    a.ty,
                    if a.value { ", value" } else { "" }
                ));
            }
        }
    }
    for name in f.keys().filter(|n| !c.contains_key(*n)) {
        problems.push(format!("{name}: a Fortran interface with no C function"));
    }
    assert!(problems.is_empty(), "meshmove.f90 does not match meshmove.h:\n  {}", problems.join("\n  "));
}

#[test]
fn fortran_types_have_the_fields_of_the_c_structs() {
    let h = c_code(&read("include/meshmove.h"));
    let lines = fortran_lines(&read("include/meshmove.f90"));
    for s in STRUCTS {
        let start = h.find(&format!("typedef struct {s} {{")).unwrap_or_else(|| panic!("{s} not in the header"));
        let body = &h[h[start..].find('{').unwrap() + start + 1..h[start..].find('}').unwrap() + start];
        let c_fields: Vec<(String, String)> = body
            .split(';')
            .map(str::trim)
            .filter(|d| !d.is_empty())
            .map(|d| {
                let (ty, name) = d.rsplit_once(char::is_whitespace).unwrap();
                (ty.trim().to_string(), name.to_string())
            })
            .collect();
        let at = lines
            .iter()
            .position(|l| l.to_lowercase().replace(' ', "") == format!("type,bind(c)::{s}"))
            .unwrap_or_else(|| panic!("no `type, bind(c) :: {s}` in meshmove.f90"));
        let mut f_fields = Vec::new();
        for l in &lines[at + 1..] {
            if l.to_lowercase().starts_with("end type") {
                break;
            }
            let (ty, _, names) = split_decl(l).unwrap();
            f_fields.extend(names.into_iter().map(|n| (ty.clone(), n)));
        }
        let want: Vec<(String, String)> = c_fields
            .iter()
            .map(|(t, n)| {
                let ft = match t.as_str() {
                    "int32_t" => "integer(c_int32_t)",
                    "double" => "real(c_double)",
                    other => panic!("{s}.{n}: C type {other} has no Fortran mapping here"),
                };
                (ft.to_string(), n.to_lowercase())
            })
            .collect();
        assert_eq!(f_fields, want, "{s}: Fortran fields (type, name) differ from the C struct's");
    }
}

#[test]
fn every_header_constant_has_a_fortran_parameter() {
    let h = c_code(&read("include/meshmove.h"));
    let raw = read("include/meshmove.h");
    let mut constants = BTreeMap::new();
    // enum values: `MESHMOVE_X = 3,`
    for part in h.split([',', '{', '}', '\n']) {
        if let Some((n, v)) = part.split_once('=') {
            let n = n.trim();
            if n.starts_with("MESHMOVE_") {
                constants.insert(n.to_string(), v.trim().to_string());
            }
        }
    }
    // #define MESHMOVE_X 3 (numbers only: not the include guard nor the attribute macro)
    for l in raw.lines() {
        let w: Vec<&str> = l.split_whitespace().collect();
        if w.len() == 3 && w[0] == "#define" && w[1].starts_with("MESHMOVE_") && w[2].parse::<i64>().is_ok() {
            constants.insert(w[1].to_string(), w[2].to_string());
        }
    }
    assert!(constants.len() > 40, "parsed only {} constants", constants.len());
    let f: String = fortran_lines(&read("include/meshmove.f90")).join("\n");
    let mut fconst = BTreeMap::new();
    for l in f.lines().filter(|l| l.to_lowercase().contains("parameter")) {
        let rest = l.split_once("::").unwrap().1;
        for item in rest.split(',') {
            if let Some((n, v)) = item.split_once('=') {
                fconst.insert(n.trim().to_string(), v.trim().to_string());
            }
        }
    }
    let problems: Vec<String> = constants
        .iter()
        .filter(|(n, v)| fconst.get(*n) != Some(*v))
        .map(|(n, v)| format!("{n} = {v} in the header, {:?} in meshmove.f90", fconst.get(n)))
        .collect();
    assert!(problems.is_empty(), "constants differ:\n  {}", problems.join("\n  "));
}

/// The module `meshmove` (the high-level layer) without comments.
fn high_level_module(f: &str) -> String {
    let start = f.find("\nmodule meshmove\n").expect("module meshmove");
    f[start..].lines().map(|l| l.find('!').map_or(l, |i| &l[..i])).collect::<Vec<_>>().join("\n")
}

#[test]
fn the_high_level_module_wraps_every_c_function() {
    let c = c_functions(&read("include/meshmove.h"));
    let module = high_level_module(&read("include/meshmove.f90"));
    let missing: Vec<&String> = c
        .keys()
        .filter(|name| {
            // a call: the name followed by an argument list
            !module.match_indices(name.as_str()).any(|(i, _)| {
                let after = module[i + name.len()..].trim_start();
                let word_end = !module[i + name.len()..].starts_with(|ch: char| ch.is_alphanumeric() || ch == '_');
                word_end && after.starts_with('(')
            })
        })
        .collect();
    assert!(missing.is_empty(), "module meshmove calls none of: {missing:?}");
}
