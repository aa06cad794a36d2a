//! Self-contained SVG histograms of the release velocities |X'| (the release model's Monte
//! Carlo returns them: `McResult::abs_um_s`) with the percentile point and the requirement
//! limit.
//!
//! Hand-written SVG (no font or system library; the style's font family); the reports embed
//! or link it.

use std::fmt::Write;

use crate::style::FONT;
use crate::{fmt_tick, nice_step};
use geodesic_util::escape::text as esc;

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
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="{FONT}" font-size="14">"#
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

/// Returns an SVG document judging one requirement on the Monte Carlo velocities: on top the
/// histogram of `values_um_s` [um/s] with the percentile point `p_um_s` (dashed) and the
/// requirement's own limit `limit_um_s` (solid red, labelled `req_label`); below, the tail on a
/// log scale (fraction of releases with |X'| above v), where the percentile is judged: the
/// exceedance `1 - probability` (0.27 % for 99.73 %) is drawn as a horizontal line, so the
/// percentile is where the curve crosses it, and the limit must lie to its right.
pub fn requirement_histogram_svg(
    values_um_s: &[f64],
    p_um_s: f64,
    probability: f64,
    limit_um_s: f64,
    req_label: &str,
    title: &str,
) -> String {
    let (w, h) = (900.0, 720.0);
    let (ml, mr) = (86.0, 30.0);
    let (t0, t1) = (60.0, 330.0); // top panel
    let (b0, b1) = (410.0, 660.0); // tail panel
    let pw = w - ml - mr;
    let n = values_um_s.len().max(1);
    let vmax = values_um_s.iter().copied().fold(0.0f64, f64::max);
    let xdata = (vmax.max(p_um_s) * 1.02).max(1e-6);
    let xmax = xdata.max(limit_um_s * 1.08);
    let x = |v: f64| ml + pw * (v / xmax).clamp(0.0, 1.0);
    let nb = 80usize;
    let mut counts = vec![0u64; nb];
    for &v in values_um_s {
        let b = ((v / xdata) * nb as f64).floor() as usize;
        counts[b.min(nb - 1)] += 1;
    }
    let cmax = counts.iter().copied().max().unwrap_or(1).max(1) as f64;
    let yc = |c: f64| t1 - (t1 - t0) * c / cmax;
    // tail: log10 of the exceedance fraction, from 1 down to 1/N (rounded down to a decade)
    let lo_dec = (1.0 / n as f64).log10().floor().min(-1.0);
    let yt = |p: f64| b0 + (b1 - b0) * (p.log10() / lo_dec).clamp(0.0, 1.0);
    let (orange, red, blue) = ("#c06000", "#c00000", "#4878a8");
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="{FONT}" font-size="14">"#
    );
    let _ = writeln!(s, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="26" text-anchor="middle" font-size="17" font-weight="bold">{}</text>"#,
        w / 2.0,
        esc(title)
    );
    // bars
    for (i, &c) in counts.iter().enumerate() {
        if c == 0 {
            continue;
        }
        let x0 = x(i as f64 * xdata / nb as f64);
        let bw = pw * xdata / xmax / nb as f64;
        let _ = writeln!(
            s,
            r#"<rect x="{x0:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="{blue}"><title>{c}</title></rect>"#,
            yc(c as f64),
            (bw * 0.95).max(0.5),
            t1 - yc(c as f64)
        );
    }
    exceedance_curve(&mut s, values_um_s, &x, &yt, blue);
    x_axes(&mut s, &[(t0, t1), (b0, b1)], &x, xmax, ml, pw);
    let cstep = nice_step(cmax / 5.0).max(1.0);
    let mut c = 0.0;
    while c <= cmax {
        let _ = writeln!(
            s,
            r#"<line x1="{0}" y1="{1:.2}" x2="{2}" y2="{1:.2}" stroke="black"/><text x="{3}" y="{4:.2}" text-anchor="end" font-size="13">{5}</text>"#,
            ml - 5.0,
            yc(c),
            ml,
            ml - 8.0,
            yc(c) + 4.5,
            c
        );
        c += cstep;
    }
    decade_ticks(&mut s, lo_dec, &yt, ml, pw);
    for (p0, p1, label) in [
        (t0, t1, "releases per bin"),
        (b0, b1, "fraction of releases above |X'| (log)"),
    ] {
        let yc = (p0 + p1) / 2.0;
        let _ = writeln!(
            s,
            r#"<text x="18" y="{yc}" text-anchor="middle" transform="rotate(-90 18 {yc})">{label}</text>"#
        );
    }
    let _ = writeln!(
        s,
        r#"<text x="{ml}" y="{}" font-weight="bold">Tail on a log scale: the {} % point is where the curve crosses {} %</text>"#,
        b0 - 12.0,
        fmt_tick(probability * 100.0),
        fmt_tick((1.0 - probability) * 100.0)
    );
    // exceedance level, percentile point and limit in both panels
    let yl = yt(1.0 - probability);
    let _ = writeln!(
        s,
        r##"<line x1="{ml}" y1="{yl:.2}" x2="{}" y2="{yl:.2}" stroke="#555" stroke-width="1.5" stroke-dasharray="2,3"/>"##,
        ml + pw
    );
    for (p0, p1) in [(t0, t1), (b0, b1)] {
        let _ = writeln!(
            s,
            r#"<line x1="{0:.2}" y1="{p0}" x2="{0:.2}" y2="{p1}" stroke="{orange}" stroke-width="2" stroke-dasharray="7,4"/><line x1="{1:.2}" y1="{p0}" x2="{1:.2}" y2="{p1}" stroke="{red}" stroke-width="2.5"/>"#,
            x(p_um_s),
            x(limit_um_s)
        );
    }
    // legend (top right of the histogram panel, inside the plot, away from the bars' labels)
    let items = [
        (format!("{n} releases, count per bin"), blue, ""),
        (
            format!(
                "{} % point: {} um/s",
                fmt_tick(probability * 100.0),
                fmt_tick(p_um_s)
            ),
            orange,
            "7,4",
        ),
        (
            format!("{req_label} limit: {} um/s", fmt_tick(limit_um_s)),
            red,
            "",
        ),
        (
            format!(
                "exceedance {} % (tail panel)",
                fmt_tick((1.0 - probability) * 100.0)
            ),
            "#555",
            "2,3",
        ),
    ];
    legend(&mut s, &items, ml + pw, t0);
    s.push_str("</svg>\n");
    s
}

/// The frame, the x ticks with their grid, and the x label of each panel `(top, bottom)`.
fn x_axes(
    s: &mut String,
    panels: &[(f64, f64)],
    x: &dyn Fn(f64) -> f64,
    xmax: f64,
    ml: f64,
    pw: f64,
) {
    let step = nice_step(xmax / 7.0);
    for &(p0, p1) in panels {
        let _ = writeln!(
            s,
            r#"<rect x="{ml}" y="{p0}" width="{pw}" height="{}" fill="none" stroke="black"/>"#,
            p1 - p0
        );
        let mut t = 0.0;
        while t <= xmax + 1e-12 {
            let _ = writeln!(
                s,
                r##"<line x1="{0:.2}" y1="{1}" x2="{0:.2}" y2="{2}" stroke="#ddd"/><line x1="{0:.2}" y1="{2}" x2="{0:.2}" y2="{3}" stroke="black"/><text x="{0:.2}" y="{4}" text-anchor="middle" font-size="13">{5}</text>"##,
                x(t),
                p0,
                p1,
                p1 + 5.0,
                p1 + 20.0,
                fmt_tick(t)
            );
            t += step;
        }
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}" text-anchor="middle">|X'| [um/s]</text>"#,
            ml + pw / 2.0,
            p1 + 40.0
        );
    }
}

/// The exceedance curve of the tail panel: every point of the last 2000 releases, a thinned
/// grid before (`x`: value [um/s] to abscissa, `yt`: exceedance fraction to ordinate).
fn exceedance_curve(
    s: &mut String,
    values_um_s: &[f64],
    x: &dyn Fn(f64) -> f64,
    yt: &dyn Fn(f64) -> f64,
    blue: &str,
) {
    let mut sorted: Vec<f64> = values_um_s
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .collect();
    sorted.sort_by(f64::total_cmp);
    let m = sorted.len();
    let step = (m / 2000).max(1);
    let mut pts = Vec::new();
    for (k, v) in sorted.iter().enumerate() {
        let above = (m - k) as f64 / m.max(1) as f64; // fraction >= v
        if m - k <= 2000 || k.is_multiple_of(step) {
            pts.push(format!("{:.2},{:.2}", x(*v), yt(above)));
        }
    }
    if !pts.is_empty() {
        let _ = writeln!(
            s,
            r#"<polyline points="{}" fill="none" stroke="{blue}" stroke-width="2"/>"#,
            pts.join(" ")
        );
    }
}

/// The decade ticks and grid of the tail panel, from 1 down to `10^lo_dec`.
fn decade_ticks(s: &mut String, lo_dec: f64, yt: &dyn Fn(f64) -> f64, ml: f64, pw: f64) {
    let mut d = 0.0;
    while d >= lo_dec {
        let p = 10f64.powf(d);
        let label = match d as i32 {
            0 => "1".to_string(),
            -1 => "0.1".to_string(),
            -2 => "0.01".to_string(),
            k => format!("1e{k}"),
        };
        let _ = writeln!(
            s,
            r##"<line x1="{ml}" y1="{0:.2}" x2="{1}" y2="{0:.2}" stroke="#ddd"/><line x1="{2}" y1="{0:.2}" x2="{ml}" y2="{0:.2}" stroke="black"/><text x="{3}" y="{4:.2}" text-anchor="end" font-size="13">{label}</text>"##,
            yt(p),
            ml + pw,
            ml - 5.0,
            ml - 8.0,
            yt(p) + 4.5
        );
        d -= 1.0;
    }
}

/// The legend box, its right edge 10 px left of `right`, its top 10 px below `top`: one line
/// per item (label, colour, dash pattern; the first drawn thick as a bar).
fn legend(s: &mut String, items: &[(String, &str, &str)], right: f64, top: f64) {
    let lw = 360.0;
    let lx = right - lw - 10.0;
    let ly = top + 10.0;
    let _ = writeln!(
        s,
        r##"<rect x="{lx}" y="{ly}" width="{lw}" height="{}" fill="white" fill-opacity="0.92" stroke="#888"/>"##,
        12.0 + 22.0 * items.len() as f64
    );
    for (i, (label, color, dash)) in items.iter().enumerate() {
        let yy = ly + 20.0 + 22.0 * i as f64;
        let _ = writeln!(
            s,
            r#"<line x1="{}" y1="{:.1}" x2="{}" y2="{:.1}" stroke="{color}" stroke-width="{}" stroke-dasharray="{dash}"/><text x="{}" y="{:.1}">{}</text>"#,
            lx + 10.0,
            yy - 5.0,
            lx + 40.0,
            yy - 5.0,
            if i == 0 { 8.0 } else { 2.5 },
            lx + 48.0,
            yy,
            esc(label)
        );
    }
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

    #[test]
    fn requirement_plot_draws_its_own_limit_and_the_tail() {
        let v: Vec<f64> = (0..10_000).map(|i| i as f64 / 10_000.0).collect();
        let s = requirement_histogram_svg(&v, 0.9973, 0.9973, 7.5, "REL-DFACS-VEL", "t");
        assert!(s.contains("REL-DFACS-VEL limit: 7.5 um/s"));
        assert!(s.contains("99.73 % point: 0.997 um/s"));
        assert!(s.contains("crosses 0.27 %"));
        assert!(s.contains(">1e-4<"), "tail axis down to 1/N");
        assert!(!s.contains("font-size=\"12\""), "no font below 13 px");
    }
}
