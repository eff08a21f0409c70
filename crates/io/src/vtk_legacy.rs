//! Reading legacy VTK files (`.vtk`) of unstructured grids, ASCII or binary, in both layouts:
//! version 2.0 to 4.2 (`CELLS n size` with each cell's point count before its points, as
//! OpenFOAM's `foamToVTK` writes) and 5.1 (`CELLS` as `OFFSETS` and `CONNECTIVITY` arrays, VTK
//! 9's and ParaView's default). vtkio reads only the first. Point and cell fields come from
//! `SCALARS`, `VECTORS`, `NORMALS` and `FIELD` data (other attributes are refused). Binary
//! data is big-endian, as the format says.

use crate::vtu_read::{Scalar, VtuPiece, MAX_COUNT};

/// Reads the piece of a legacy `.vtk` file given as bytes; errors are messages for the file.
pub(crate) fn parse_vtk_legacy(bytes: &[u8]) -> Result<VtuPiece, String> {
    let mut r = Reader { bytes, at: 0 };
    let version = r.line().ok_or("empty file")?;
    if !version.starts_with("# vtk DataFile") {
        return Err("not a legacy VTK file (no '# vtk DataFile' first line)".into());
    }
    r.line().ok_or("no title line")?;
    let binary = match r.keyword_line()?.as_deref() {
        Some("ASCII") => false,
        Some("BINARY") => true,
        other => return Err(format!("expected ASCII or BINARY, found {other:?}")),
    };
    let dataset = r.keyword_line()?.unwrap_or_default();
    if dataset.split_whitespace().nth(1) != Some("UNSTRUCTURED_GRID") {
        return Err(format!(
            "'{dataset}': only an UNSTRUCTURED_GRID data set is read"
        ));
    }
    let mut piece = VtuPiece {
        points: Vec::new(),
        connectivity: Vec::new(),
        offsets: Vec::new(),
        types: Vec::new(),
        point_data: Vec::new(),
        cell_data: Vec::new(),
    };
    // The attributes being read: of the points (true) or of the cells (false), and their count.
    let mut section: Option<(bool, usize)> = None;
    while let Some(line) = r.keyword_line()? {
        let f: Vec<&str> = line.split_whitespace().collect();
        // (Counts beyond any memory are refused, so that products of them cannot overflow.)
        let count = |k: usize| -> Result<usize, String> {
            f.get(k)
                .and_then(|t| t.parse().ok())
                .filter(|&c: &usize| c < MAX_COUNT)
                .ok_or_else(|| format!("'{line}': a count expected"))
        };
        match f[0] {
            "POINTS" => piece.points = r.values(3 * count(1)?, scalar(f.get(2))?, binary)?,
            "CELLS" => {
                let (n, size) = (count(1)?, count(2)?);
                // 5.1: OFFSETS and CONNECTIVITY follow; before: counts and points.
                let save = r.at;
                match r.keyword_line()? {
                    Some(next) if next.starts_with("OFFSETS") => {
                        let t = scalar(next.split_whitespace().nth(1).as_ref())?;
                        let offsets = r.values(n, t, binary)?;
                        let next = r.keyword_line()?.unwrap_or_default();
                        if !next.starts_with("CONNECTIVITY") {
                            return Err(format!("'{next}': CONNECTIVITY expected"));
                        }
                        let t = scalar(next.split_whitespace().nth(1).as_ref())?;
                        piece.connectivity = r.values(size, t, binary)?;
                        piece.offsets = offsets.get(1..).unwrap_or_default().to_vec();
                    }
                    _ => {
                        r.at = save;
                        let all = r.values(size, Scalar::I32, binary)?;
                        let mut k = 0;
                        for _ in 0..n {
                            let m = *all.get(k).ok_or("CELLS is shorter than its size")?;
                            if !(m >= 0.0 && m.fract() == 0.0) {
                                return Err(format!("a cell of {m} points"));
                            }
                            let m = m as usize;
                            let cell = (k + 1)
                                .checked_add(m)
                                .and_then(|end| all.get(k + 1..end))
                                .ok_or("CELLS is shorter than its size")?;
                            piece.connectivity.extend_from_slice(cell);
                            piece.offsets.push(piece.connectivity.len() as f64);
                            k += 1 + m;
                        }
                    }
                }
            }
            "CELL_TYPES" => piece.types = r.values(count(1)?, Scalar::I32, binary)?,
            "POINT_DATA" | "CELL_DATA" => {
                let of_points = f[0] == "POINT_DATA";
                let (n, have) = if of_points {
                    (count(1)?, piece.points.len() / 3)
                } else {
                    (count(1)?, piece.types.len())
                };
                if n != have {
                    return Err(format!("'{line}': the mesh has {have}"));
                }
                section = Some((of_points, n));
            }
            "METADATA" => r.skip_metadata()?,
            "SCALARS" | "VECTORS" | "NORMALS" | "FIELD" if section.is_some() => {
                let (of_points, n) = section.expect("a data section");
                let list = if of_points {
                    &mut piece.point_data
                } else {
                    &mut piece.cell_data
                };
                let name = f.get(1).copied().unwrap_or("").to_string();
                match f[0] {
                    "SCALARS" => {
                        let comps =
                            match f.get(3) {
                                None => 1,
                                Some(_) => {
                                    count(3).ok().filter(|c| (1..=4).contains(c)).ok_or_else(
                                        || format!("'{line}': SCALARS have 1 to 4 components"),
                                    )?
                                }
                            };
                        let t = scalar(f.get(2))?;
                        let save = r.at;
                        if !r
                            .keyword_line()?
                            .unwrap_or_default()
                            .starts_with("LOOKUP_TABLE")
                        {
                            r.at = save;
                        }
                        let values = r.values(comps * n, t, binary)?;
                        list.push((name, comps, values));
                    }
                    "VECTORS" | "NORMALS" => {
                        let values = r.values(3 * n, scalar(f.get(2))?, binary)?;
                        list.push((name, 3, values));
                    }
                    _ => {
                        for _ in 0..count(2)? {
                            let a = r.keyword_line()?.unwrap_or_default();
                            let g: Vec<&str> = a.split_whitespace().collect();
                            let num = |k: usize| -> Result<usize, String> {
                                g.get(k)
                                    .and_then(|t| t.parse().ok())
                                    .filter(|&c: &usize| c < MAX_COUNT)
                                    .ok_or_else(|| format!("'{a}': a field array expected"))
                            };
                            let (comps, tuples) = (num(1)?, num(2)?);
                            let values = r.values(comps * tuples, scalar(g.get(3))?, binary)?;
                            r.skip_metadata_if_next()?;
                            if tuples == n {
                                list.push((g[0].to_string(), comps, values));
                            }
                        }
                    }
                }
                r.skip_metadata_if_next()?;
            }
            other => return Err(format!("'{other}': a section this reader does not know")),
        }
    }
    if piece.types.len() != piece.offsets.len() {
        return Err(format!(
            "{} cell types for {} cells",
            piece.types.len(),
            piece.offsets.len()
        ));
    }
    Ok(piece)
}

fn scalar(name: Option<&&str>) -> Result<Scalar, String> {
    let name = name.copied().unwrap_or("");
    Ok(match name {
        "bit" | "unsigned_char" => Scalar::U8,
        "char" => Scalar::I8,
        "unsigned_short" => Scalar::U16,
        "short" => Scalar::I16,
        "unsigned_int" => Scalar::U32,
        "int" => Scalar::I32,
        "unsigned_long" | "vtktypeuint64" => Scalar::U64,
        "long" | "vtktypeint64" | "vtkIdType" => Scalar::I64,
        "float" => Scalar::F32,
        "double" => Scalar::F64,
        _ => return Err(format!("data type '{name}' is not a number type")),
    })
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    /// The next line (without its end), or `None` at the end.
    fn line(&mut self) -> Option<String> {
        if self.at >= self.bytes.len() {
            return None;
        }
        let rest = &self.bytes[self.at..];
        let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        self.at += (end + 1).min(rest.len());
        Some(String::from_utf8_lossy(&rest[..end]).trim().to_string())
    }

    /// The next line that is not blank.
    fn keyword_line(&mut self) -> Result<Option<String>, String> {
        while let Some(l) = self.line() {
            if !l.is_empty() {
                return Ok(Some(l));
            }
        }
        Ok(None)
    }

    /// 5.1's `METADATA` block: lines up to a blank one.
    fn skip_metadata(&mut self) -> Result<(), String> {
        while let Some(l) = self.line() {
            if l.is_empty() {
                break;
            }
        }
        Ok(())
    }

    fn skip_metadata_if_next(&mut self) -> Result<(), String> {
        let save = self.at;
        match self.keyword_line()? {
            Some(l) if l == "METADATA" => self.skip_metadata(),
            _ => {
                self.at = save;
                Ok(())
            }
        }
    }

    /// `n` values of type `t`: whitespace-separated text, or big-endian binary.
    fn values(&mut self, n: usize, t: Scalar, binary: bool) -> Result<Vec<f64>, String> {
        if binary {
            let size = n.checked_mul(t.size()).ok_or("a section too large")?;
            let data = self
                .at
                .checked_add(size)
                .and_then(|end| self.bytes.get(self.at..end))
                .ok_or("the binary data ends early")?;
            self.at += size;
            // The newline after the block.
            if self.bytes.get(self.at) == Some(&b'\n') {
                self.at += 1;
            }
            return t.decode(data, true);
        }
        let mut out = Vec::with_capacity(n.min(1 << 24));
        while out.len() < n {
            let line = self.line().ok_or("the file ends inside a section")?;
            for token in line.split_ascii_whitespace() {
                out.push(
                    token.parse::<f64>().map_err(|_| {
                        format!("'{}' is not a number", crate::text::shorten(token))
                    })?,
                );
            }
        }
        if out.len() != n {
            return Err(format!("{} values where {n} were expected", out.len()));
        }
        Ok(out)
    }
}
