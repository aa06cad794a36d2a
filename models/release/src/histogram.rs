//! A self-contained SVG histogram of |X'| with the 99.73 % line and the requirement limit.
//!
//! Hand-written SVG (no font or system library); the reports embed or link it.

use std::fmt::Write;

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Returns an SVG document: histogram of `values_um_s` [um/s], a dashed line at `p9973_um_s`
/// and a red line at `limit_um_s` (if given).
pub fn histogram_svg(
    values_um_s: &[f64],
    p9973_um_s: f64,
    limit_um_s: Option<f64>,
    title: &str,
) -> String {
    let (w, h) = (720.0, 420.0);
    let (ml, mr, mt, mb) = (70.0, 20.0, 40.0, 50.0);
    let pw = w - ml - mr;
    let ph = h - mt - mb;
    let vmax = values_um_s.iter().copied().fold(0.0f64, f64::max);
    // 80 bins over the data; the axis extends to the limit if it lies beyond
    let xdata = (vmax.max(p9973_um_s) * 1.02).max(1e-6);
    let xmax = xdata.max(limit_um_s.unwrap_or(0.0) * 1.05);
    let nb = 80usize;
    let mut counts = vec![0u64; nb];
    for &v in values_um_s {
        let b = ((v / xdata) * nb as f64).floor() as usize;
        counts[b.min(nb - 1)] += 1;
    }
    let cmax = counts.iter().copied().max().unwrap_or(1).max(1) as f64;
    let x = |v: f64| ml + pw * v / xmax;
    let y = |c: f64| mt + ph * (1.0 - c / cmax);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="22" text-anchor="middle" font-size="14">{}</text>"#,
        w / 2.0,
        esc(title)
    );
    for (i, &c) in counts.iter().enumerate() {
        if c == 0 {
            continue;
        }
        let x0 = x(i as f64 * xdata / nb as f64);
        let bw = pw * xdata / xmax / nb as f64;
        let _ = writeln!(
            s,
            r##"<rect x="{x0:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="#4878a8"><title>{c}</title></rect>"##,
            y(c as f64),
            bw * 0.95,
            mt + ph - y(c as f64)
        );
    }
    // axes and ticks
    let _ = writeln!(
        s,
        r#"<line x1="{ml}" y1="{}" x2="{}" y2="{}" stroke="black"/>"#,
        mt + ph,
        ml + pw,
        mt + ph
    );
    let _ = writeln!(
        s,
        r#"<line x1="{ml}" y1="{mt}" x2="{ml}" y2="{}" stroke="black"/>"#,
        mt + ph
    );
    let step = nice_step(xmax / 6.0);
    let mut t = 0.0;
    while t <= xmax {
        let _ = writeln!(
            s,
            r#"<line x1="{0:.2}" y1="{1}" x2="{0:.2}" y2="{2}" stroke="black"/><text x="{0:.2}" y="{3}" text-anchor="middle">{4}</text>"#,
            x(t),
            mt + ph,
            mt + ph + 5.0,
            mt + ph + 18.0,
            fmt_tick(t)
        );
        t += step;
    }
    let cstep = nice_step(cmax / 5.0).max(1.0);
    let mut c = 0.0;
    while c <= cmax {
        let _ = writeln!(
            s,
            r#"<line x1="{0}" y1="{1:.2}" x2="{2}" y2="{1:.2}" stroke="black"/><text x="{3}" y="{4:.2}" text-anchor="end">{5}</text>"#,
            ml - 5.0,
            y(c),
            ml,
            ml - 8.0,
            y(c) + 4.0,
            c
        );
        c += cstep;
    }
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" text-anchor="middle">|X'| [um/s]</text>"#,
        ml + pw / 2.0,
        h - 10.0
    );
    let _ = writeln!(
        s,
        r#"<text x="16" y="{}" text-anchor="middle" transform="rotate(-90 16 {})">releases per bin</text>"#,
        mt + ph / 2.0,
        mt + ph / 2.0
    );
    let _ = writeln!(
        s,
        r##"<line x1="{0:.2}" y1="{1}" x2="{0:.2}" y2="{2}" stroke="#d08000" stroke-width="2" stroke-dasharray="6,4"/><text x="{3:.2}" y="{4}" fill="#d08000">99.73 %: {5:.3} um/s</text>"##,
        x(p9973_um_s),
        mt,
        mt + ph,
        x(p9973_um_s) + 4.0,
        mt + 14.0,
        p9973_um_s
    );
    if let Some(l) = limit_um_s {
        let _ = writeln!(
            s,
            r##"<line x1="{0:.2}" y1="{1}" x2="{0:.2}" y2="{2}" stroke="#c00000" stroke-width="2"/><text x="{3:.2}" y="{4}" fill="#c00000" text-anchor="end">limit {5} um/s</text>"##,
            x(l),
            mt,
            mt + ph,
            x(l) - 4.0,
            mt + 30.0,
            l
        );
    }
    s.push_str("</svg>\n");
    s
}

fn nice_step(raw: f64) -> f64 {
    if raw <= 0.0 || !raw.is_finite() {
        return 1.0;
    }
    let p = 10f64.powf(raw.log10().floor());
    let m = raw / p;
    let n = if m <= 1.0 {
        1.0
    } else if m <= 2.0 {
        2.0
    } else if m <= 5.0 {
        5.0
    } else {
        10.0
    };
    n * p
}

fn fmt_tick(v: f64) -> String {
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn svg_has_lines_and_bars() {
        let v: Vec<f64> = (0..1000).map(|i| i as f64 / 1000.0).collect();
        let s = histogram_svg(&v, 0.997, Some(5.0), "t <x>");
        assert!(s.starts_with("<svg"));
        assert!(s.contains("99.73 %: 0.997 um/s"));
        assert!(s.contains("limit 5 um/s"));
        assert!(s.contains("t &lt;x&gt;"));
        assert!(s.matches("<rect").count() > 10);
    }
}
