//! Fuzz-style tests of the 3D surface readers: every truncation of valid files, random token
//! replacements (huge counts, negative and non-finite numbers, missing fields) and random bytes
//! must give `Ok` or an error, never a panic or a huge allocation. Deterministic (a fixed-seed
//! generator) and fast (a few thousand small parses).

use std::path::Path;

use delmesh_io::{
    parse_medit, parse_msh, parse_msh_bytes, parse_obj, parse_off, parse_ply, parse_poly_any,
    parse_smesh, parse_stl, parse_tetgen_poly, IoError, SurfaceFile,
};

/// A small xorshift generator: no dependency, same sequence everywhere.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

type Parser = fn(&[u8]) -> Result<SurfaceFile, IoError>;

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

const PARSERS: [(&str, Parser); 10] = [
    ("smesh", |b| parse_smesh(&text(b), Path::new("g.smesh"))),
    ("poly", |b| parse_tetgen_poly(&text(b), Path::new("g.poly"))),
    ("poly any", |b| {
        parse_poly_any(&text(b), Path::new("g.poly")).map(|_| SurfaceFile::default())
    }),
    ("off", |b| parse_off(&text(b), Path::new("g.off"))),
    ("stl", |b| parse_stl(b, Path::new("g.stl"))),
    ("obj", |b| parse_obj(&text(b), Path::new("g.obj"))),
    ("mesh", |b| parse_medit(&text(b), Path::new("g.mesh"))),
    ("msh", |b| parse_msh(&text(b), Path::new("g.msh"))),
    // Binary .msh files are bytes, not text.
    ("msh bytes", |b| parse_msh_bytes(b, Path::new("g.msh"))),
    ("ply", |b| parse_ply(b, Path::new("g.ply"))),
];

/// Valid inputs of every format, the seeds of the mutations.
fn samples() -> Vec<Vec<u8>> {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let mut v: Vec<Vec<u8>> = [
        "8 3 0 1\n1 0 0 0 1\n2 1 0 0 1\n3 1 1 0 1\n4 0 1 0 1\n5 0 0 1 2\n6 1 0 1 2\n\
         7 1 1 1 2\n8 0 1 1 2\n2 1\n4 1 2 3 4 1\n4 5 6 7 8 2\n1\n1 0.5 0.5 0.5\n\
         1\n1 0.1 0.1 0.1 7 0.01\n",
        "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n2 1\n2 1 5\n3 0 1 2\n1 3\n\
         1 0.2 0.2 0\n1 0 2\n4 0 1 2 3\n0\n",
        "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n4 0 1 2 3 255 0 0\n",
        "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n\
         endloop\nendfacet\nendsolid a\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\ng a\nf 1/1 2//2 -1/1/1\nusemtl m\nf 3 2 1\n",
        "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 1\n1 0 0 1\n0 1 0 1\n\
         0 0 1 1\nTriangles\n1\n1 2 3 4\nTetrahedra\n1\n1 2 3 4 2\nEnd\n",
        "ply\nformat ascii 1.0\ncomment c\nelement vertex 4\nproperty float x\nproperty float y\n\
         property float z\nproperty uchar red\nelement face 2\nproperty list uchar int \
         vertex_indices\nelement edge 1\nproperty int a\nproperty int b\nend_header\n\
         0 0 0 1\n1 0 0 2\n0 1 0 3\n0 0 1 4\n3 0 1 2\n4 0 1 2 3\n0 1\n",
    ]
    .iter()
    .map(|s| s.as_bytes().to_vec())
    .collect();
    for f in [
        "gmsh_box22.msh",
        "gmsh_box41.msh",
        "gmsh_box41_parametric.msh",
        "gmsh_box22_binary.msh",
        "gmsh_box41_binary.msh",
        "gmsh_box41_parametric_binary.msh",
        "gmsh_periodic22_binary.msh",
        "gmsh_periodic41_binary.msh",
        "gmsh_box.mesh",
        "gmsh_box_binary.stl",
    ] {
        v.push(std::fs::read(data.join(f)).unwrap());
    }
    // A binary PLY (big-endian): 4 points, 2 faces.
    let mut ply = b"ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty double x\n\
        property double y\nproperty double z\nelement face 2\nproperty list uchar uint \
        vertex_indices\nend_header\n"
        .to_vec();
    for p in [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0f64],
    ] {
        for x in p {
            ply.extend(x.to_be_bytes());
        }
    }
    for f in [&[0u32, 1, 2][..], &[0, 1, 2, 3]] {
        ply.push(f.len() as u8);
        for &i in f {
            ply.extend(i.to_be_bytes());
        }
    }
    v.push(ply);
    v
}

const SPECIAL: [&str; 14] = [
    "18446744073709551615",
    "18446744073709551616",
    "4294967296",
    "2147483648",
    "-1",
    "0",
    "nan",
    "inf",
    "-inf",
    "1e400",
    "\"",
    "$EndNodes",
    "$Entities",
    "",
];

#[test]
fn truncations_never_panic() {
    for sample in samples() {
        // Every prefix of the small samples; a stride through the larger ones.
        let step = (sample.len() / 600).max(1);
        for end in (0..=sample.len()).step_by(step) {
            for (_, parse) in PARSERS {
                let _ = parse(&sample[..end]);
            }
        }
    }
}

#[test]
fn token_replacements_never_panic() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for sample in samples() {
        let s = text(&sample);
        let tokens: Vec<&str> = s.split_whitespace().collect();
        for _ in 0..150 {
            let mut toks = tokens.clone();
            for _ in 0..1 + rng.below(3) {
                let i = rng.below(toks.len());
                toks[i] = SPECIAL[rng.below(SPECIAL.len())];
            }
            // Keep the line structure of the original, token for token.
            let mut out = String::with_capacity(s.len() + 64);
            let mut k = 0;
            for line in s.lines() {
                for _ in line.split_whitespace() {
                    out.push_str(toks[k]);
                    out.push(' ');
                    k += 1;
                }
                out.push('\n');
            }
            for (_, parse) in PARSERS {
                let _ = parse(out.as_bytes());
            }
        }
    }
}

#[test]
fn random_bytes_and_byte_flips_never_panic() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for _ in 0..300 {
        let len = rng.below(300);
        let bytes: Vec<u8> = (0..len).map(|_| rng.next() as u8).collect();
        for (_, parse) in PARSERS {
            let _ = parse(&bytes);
        }
    }
    for sample in samples() {
        for _ in 0..60 {
            let mut b = sample.clone();
            for _ in 0..1 + rng.below(4) {
                let i = rng.below(b.len());
                match rng.below(3) {
                    0 => b[i] = rng.next() as u8,
                    1 => {
                        b.remove(i);
                    }
                    _ => b.insert(i, b"0123456789 -.e\n$\"#/"[rng.below(19)]),
                }
            }
            for (_, parse) in PARSERS {
                let _ = parse(&b);
            }
        }
    }
}

#[test]
fn huge_counts_in_short_files_are_errors_without_allocating() {
    let cases: [(&str, Parser); 7] = [
        ("18446744073709551615 3 0 0\n", PARSERS[0].1),
        (
            "3 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n18446744073709551615 0\n",
            PARSERS[0].1,
        ),
        (
            "3 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n1 0\n18446744073709551615 5\n",
            PARSERS[1].1,
        ),
        (
            "OFF\n18446744073709551615 18446744073709551615 0\n",
            PARSERS[3].1,
        ),
        (
            "MeshVersionFormatted 2\nDimension 3\nVertices 18446744073709551615\n",
            PARSERS[6].1,
        ),
        (
            "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n18446744073709551615 1 1 1\n",
            PARSERS[7].1,
        ),
        (
            "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Elements\n18446744073709551615\n",
            PARSERS[7].1,
        ),
    ];
    for (t, parse) in cases {
        assert!(parse(t.as_bytes()).is_err(), "{t:?}");
    }
    // Binary .msh files whose counts claim 2^64 - 1 records: nodes of 2.2, node blocks and
    // nodes, entities, element blocks and elements of 4.1.
    let format41 = b"$MeshFormat\n4.1 1 8\n\x01\0\0\0\n$EndMeshFormat\n".as_slice();
    let max = u64::MAX.to_le_bytes();
    let cases: [Vec<u8>; 6] = [
        b"$MeshFormat\n2.2 1 8\n\x01\0\0\0\n$EndMeshFormat\n$Nodes\n18446744073709551615\n"
            .to_vec(),
        [format41, b"$Nodes\n", &max, &[0; 24]].concat(),
        [
            format41,
            b"$Nodes\n",
            &1u64.to_le_bytes(),
            &[0; 24],
            &[0; 12],
            &max,
        ]
        .concat(),
        [format41, b"$Entities\n", &max, &max, &max, &max].concat(),
        [format41, b"$Elements\n", &max, &[0; 24]].concat(),
        [
            format41,
            b"$Elements\n",
            &1u64.to_le_bytes(),
            &[0; 24],
            &[0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0],
            &max,
        ]
        .concat(),
    ];
    for b in cases {
        assert!(parse_msh_bytes(&b, Path::new("g.msh")).is_err(), "{b:?}");
    }
    // A binary STL header claiming 2^32 - 1 triangles in a 84-byte file.
    let mut b = vec![0u8; 80];
    b.extend_from_slice(&u32::MAX.to_le_bytes());
    assert!(parse_stl(&b, Path::new("g.stl")).is_err());
}
