//! Reading a 64,000-tensor field (40³ points, Float32, 9 components): XML image data with raw
//! appended data, and the same as a legacy binary file. Target: ≤ 0.1 s per read (release).

use std::io::Write;
use std::path::{Path, PathBuf};

use criterion::{Criterion, criterion_group, criterion_main};
use tensorglyph::field::vtk::{ReadOptions, read_field};

const N: usize = 40;

fn tensor(i: usize) -> [f32; 9] {
    let a = (i as f32 * 0.37).sin();
    let b = (i as f32 * 0.11).cos();
    [
        1.0 + a,
        0.1 * b,
        0.2,
        0.1 * b,
        2.0 - b,
        0.3 * a,
        0.2,
        0.3 * a,
        0.5,
    ]
}

/// `.vti` with one 9-component Float32 point array in raw appended data, UInt64 header.
fn write_vti(dir: &Path) -> PathBuf {
    let n = N * N * N;
    let nbytes = (n * 9 * 4) as u64;
    let path = dir.join("bench.vti");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    write!(
        f,
        r#"<?xml version="1.0"?>
<VTKFile type="ImageData" version="1.0" byte_order="LittleEndian" header_type="UInt64">
  <ImageData WholeExtent="0 {m} 0 {m} 0 {m}" Origin="0 0 0" Spacing="0.5 0.5 0.5" Direction="1 0 0 0 1 0 0 0 1">
    <Piece Extent="0 {m} 0 {m} 0 {m}">
      <PointData Tensors="T">
        <DataArray type="Float32" Name="T" NumberOfComponents="9" format="appended" offset="0"/>
      </PointData>
      <CellData/>
    </Piece>
  </ImageData>
  <AppendedData encoding="raw">
   _"#,
        m = N - 1
    )
    .unwrap();
    f.write_all(&nbytes.to_le_bytes()).unwrap();
    for i in 0..n {
        for v in tensor(i) {
            f.write_all(&v.to_le_bytes()).unwrap();
        }
    }
    f.write_all(b"\n  </AppendedData>\n</VTKFile>\n").unwrap();
    path
}

/// The same field as a legacy binary file (big-endian).
fn write_legacy(dir: &Path) -> PathBuf {
    let n = N * N * N;
    let path = dir.join("bench.vtk");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    write!(
        f,
        "# vtk DataFile Version 4.2\nbench\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS {N} {N} {N}\nSPACING 0.5 0.5 0.5\nORIGIN 0 0 0\nPOINT_DATA {n}\nTENSORS T float\n"
    )
    .unwrap();
    for i in 0..n {
        for v in tensor(i) {
            f.write_all(&v.to_be_bytes()).unwrap();
        }
    }
    f.write_all(b"\n").unwrap();
    path
}

fn bench(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let opts = ReadOptions::default();
    for (name, path) in [
        ("vti_raw_appended_64k", write_vti(dir.path())),
        ("legacy_binary_64k", write_legacy(dir.path())),
    ] {
        let f = read_field(&path, &opts).unwrap();
        assert_eq!(f.len(), N * N * N);
        c.bench_function(name, |b| b.iter(|| read_field(&path, &opts).unwrap()));
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
