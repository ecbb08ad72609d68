//! `clients/c/upm_messages.h`, the messages for C and C++ users of
//! iceoryx2's C/C++ bindings, is generated from the Rust layouts: this test
//! renders it and fails if the committed file differs (regenerate with
//! `UPM_BLESS=1 cargo test -p ipc-types --test c_header`), then has the C
//! compiler check every size and offset the header asserts.

mod wire_layout;

use std::process::Command;

use ipc_types::{
    MAX_CURLS, MAX_PARTS, MAX_SHAPE_VERTICES, MAX_SLOTS, PROTOCOL_VERSION, SHAPE_DISC, SHAPE_POINT,
    SHAPE_POLYGON, service_names,
};

const HEADER: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../clients/c/upm_messages.h");

/// A Rust field type as C: `u32` → `uint32_t`, `[PartState; 64]` → element
/// type and array lengths, outermost first (`[[f64; 2]; 8]` → `double`,
/// [8, 2]).
fn c_type(ty: &str) -> (String, Vec<String>) {
    let scalar = |t: &str| match t {
        "u8" => "uint8_t".to_owned(),
        "u32" => "uint32_t".to_owned(),
        "u64" => "uint64_t".to_owned(),
        "i64" => "int64_t".to_owned(),
        "f64" => "double".to_owned(),
        other => format!("upm_{other}"),
    };
    // The outer length follows the last "; " (the element may be an array).
    match ty.strip_prefix('[').and_then(|t| t.strip_suffix(']')).and_then(|t| t.rsplit_once("; ")) {
        Some((elem, n)) => {
            let (t, mut dims) = c_type(elem);
            dims.insert(0, n.to_owned());
            (t, dims)
        }
        None => (scalar(ty), Vec::new()),
    }
}

/// A field name C++ can use (`class` is a C++ keyword).
fn c_name(name: &str) -> String {
    if name == "class" { "class_".to_owned() } else { name.to_owned() }
}

fn render() -> String {
    let mut layouts = wire_layout::all();
    let mut out = String::from(
        "/* UPM wire messages for C and C++ (iceoryx2's C/C++ bindings).\n \
         * GENERATED from the Rust types by ipc-types/tests/c_header.rs: do not edit.\n \
         * The contract around them (services, settings, units, ranges): docs/protocol.md. */\n\
         #ifndef UPM_MESSAGES_H\n#define UPM_MESSAGES_H\n\n#include <stddef.h>\n#include <stdint.h>\n\n\
         #ifdef __cplusplus\n#define UPM_STATIC_ASSERT static_assert\n#define UPM_ALIGNOF alignof\n\
         #else\n#define UPM_STATIC_ASSERT _Static_assert\n#define UPM_ALIGNOF _Alignof\n#endif\n\n",
    );
    out += &format!("#define UPM_PROTOCOL_VERSION {PROTOCOL_VERSION}u\n");
    out += &format!(
        "#define UPM_MAX_PARTS {MAX_PARTS}\n#define UPM_MAX_CURLS {MAX_CURLS}\n#define UPM_MAX_SLOTS {MAX_SLOTS}\n"
    );
    out += &format!("#define UPM_MAX_SHAPE_VERTICES {MAX_SHAPE_VERTICES}\n");
    out += &format!(
        "#define UPM_MAX_CENTERS {}\n#define UPM_RIG_PREFIX_BYTES {}\n",
        ipc_types::MAX_CENTERS,
        ipc_types::RIG_PREFIX_BYTES
    );
    out += &format!(
        "#define UPM_MAX_PICK_POSES {}\n#define UPM_FEED_RECENT_PICKS {}\n",
        ipc_types::MAX_PICK_POSES,
        ipc_types::FEED_RECENT_PICKS
    );
    out += &format!("#define UPM_RECIPE_PATH_BYTES {}\n", ipc_types::RECIPE_PATH_BYTES);
    // PartState.shape codes.
    for (name, code) in [("POINT", SHAPE_POINT), ("DISC", SHAPE_DISC), ("POLYGON", SHAPE_POLYGON)] {
        out += &format!("#define UPM_SHAPE_{name} {code}u\n");
    }
    for s in service_names::ALL.iter().chain([&service_names::INBOX_EVENT]) {
        let name = s.trim_start_matches("upm/").replace('/', "_").to_uppercase();
        out += &format!("#define UPM_SERVICE_{name} \"{s}\"\n");
    }
    out += "\n";
    // Inner types first: emit a type once every struct it contains is out.
    let mut emitted: Vec<&str> = Vec::new();
    while !layouts.is_empty() {
        let ready = layouts
            .iter()
            .position(|l| {
                l.fields.iter().all(|f| {
                    let (t, _) = c_type(&f.ty);
                    !t.starts_with("upm_") || emitted.contains(&t.trim_start_matches("upm_"))
                })
            })
            .expect("no cycle among the payload types");
        let l = layouts.remove(ready);
        out +=
            &format!("/* iceoryx2 type name \"{}\", {} bytes, align {} */\n", l.type_name, l.size, l.align);
        out += &format!("#define UPM_{}_TYPE_NAME \"{}\"\n", l.rust.to_uppercase(), l.type_name);
        out += "typedef struct {\n";
        for f in &l.fields {
            let (t, dims) = c_type(&f.ty);
            let dims: String = dims.iter().map(|n| format!("[{n}]")).collect();
            out += &format!("    {t} {}{dims};\n", c_name(f.name));
        }
        out += &format!("}} upm_{};\n", l.rust);
        out += &format!("UPM_STATIC_ASSERT(sizeof(upm_{0}) == {1}, \"upm_{0} size\");\n", l.rust, l.size);
        out +=
            &format!("UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_{0}) == {1}, \"upm_{0} align\");\n", l.rust, l.align);
        for f in &l.fields {
            out += &format!(
                "UPM_STATIC_ASSERT(offsetof(upm_{0}, {1}) == {2}, \"upm_{0}.{1} offset\");\n",
                l.rust,
                c_name(f.name),
                f.offset
            );
        }
        out += "\n";
        emitted.push(l.rust);
    }
    out + "#endif /* UPM_MESSAGES_H */\n"
}

#[test]
fn the_c_header_is_generated_from_the_rust_types_and_compiles() {
    let want = render();
    if std::env::var_os("UPM_BLESS").is_some() {
        std::fs::write(HEADER, &want).expect("write the header");
    }
    let have = std::fs::read_to_string(HEADER).unwrap_or_default();
    assert!(
        have == want,
        "{HEADER} differs from the Rust types; regenerate: UPM_BLESS=1 cargo test -p ipc-types --test c_header"
    );
    // The C and C++ compilers check their own layout against every size and
    // offset the header asserts.
    for (cc, lang) in [("cc", ["-std=c11", "-x", "c"]), ("c++", ["-std=c++17", "-x", "c++"])] {
        let out =
            Command::new(cc).args(lang).args(["-fsyntax-only", HEADER]).output().expect("compiler runs");
        assert!(out.status.success(), "{cc}: {}", String::from_utf8_lossy(&out.stderr));
    }
}
