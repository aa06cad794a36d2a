//! geodesic_util::stats against reference values computed independently with SciPy
//! (`stats_reference.py` beside this file wrote `stats_reference.json`).

use geodesic_util::stats::{
    binomial_cdf, binomial_sf, clopper_pearson_lower, clopper_pearson_upper, quantile_lower_rank,
    quantile_upper_rank,
};
use serde_json::Value;

fn reference() -> Value {
    serde_json::from_str(include_str!("stats_reference.json")).unwrap()
}

fn rank(v: &Value) -> Option<u64> {
    v.as_u64()
}

#[test]
fn order_statistic_ranks_match_scipy() {
    for c in reference()["quantile_ranks"].as_array().unwrap() {
        let (n, p, conf) = (
            c["n"].as_u64().unwrap(),
            c["p"].as_f64().unwrap(),
            c["c"].as_f64().unwrap(),
        );
        assert_eq!(
            quantile_upper_rank(n, p, conf),
            rank(&c["upper_rank"]),
            "upper rank n {n} p {p} c {conf}"
        );
        assert_eq!(
            quantile_lower_rank(n, p, conf),
            rank(&c["lower_rank"]),
            "lower rank n {n} p {p} c {conf}"
        );
    }
}

#[test]
fn clopper_pearson_bounds_match_scipy() {
    for c in reference()["clopper_pearson"].as_array().unwrap() {
        let (k, n, conf) = (
            c["k"].as_u64().unwrap(),
            c["n"].as_u64().unwrap(),
            c["c"].as_f64().unwrap(),
        );
        let (lo, hi) = (c["lower"].as_f64().unwrap(), c["upper"].as_f64().unwrap());
        let got_lo = clopper_pearson_lower(k, n, conf);
        let got_hi = clopper_pearson_upper(k, n, conf);
        assert!(
            (got_lo - lo).abs() <= 1e-10,
            "lower {k}/{n}: {got_lo} vs {lo}"
        );
        assert!(
            (got_hi - hi).abs() <= 1e-10,
            "upper {k}/{n}: {got_hi} vs {hi}"
        );
    }
}

#[test]
fn binomial_tails_match_scipy() {
    for c in reference()["binomial"].as_array().unwrap() {
        let (k, n, p) = (
            c["k"].as_u64().unwrap(),
            c["n"].as_u64().unwrap(),
            c["p"].as_f64().unwrap(),
        );
        let (cdf, sf) = (c["cdf"].as_f64().unwrap(), c["sf"].as_f64().unwrap());
        let got = binomial_cdf(k, n, p);
        assert!(
            (got - cdf).abs() <= 1e-9 * cdf.max(1e-300) + 1e-14,
            "cdf({k}; {n}, {p}) {got} vs {cdf}"
        );
        let got = binomial_sf(k, n, p);
        assert!(
            (got - sf).abs() <= 1e-9 * sf.max(1e-300) + 1e-14,
            "sf({k}; {n}, {p}) {got} vs {sf}"
        );
    }
}
