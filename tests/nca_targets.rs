//! Training targets: area resampling to the training grid and white balance.

use xylem::Image2;
use xylem::nca::train::targets::resample;

#[test]
fn shrinking_averages_blocks_and_keeps_the_mean() {
    let data: Vec<f32> = (0..36).map(|v| v as f32).collect();
    let img = Image2::from_data(6, 6, 1, data).unwrap();
    let half = resample(&img, 3);
    // Top-left 2 x 2 block: 0, 1, 6, 7.
    assert!((half.get(0, 0, 0) - 3.5).abs() < 1e-5);
    assert!((half.get(2, 2, 0) - (28.0 + 29.0 + 34.0 + 35.0) / 4.0).abs() < 1e-5);
    // A non-integer factor (6 -> 4) still preserves the mean.
    let odd = resample(&img, 4);
    assert!((odd.channel_means()[0] - img.channel_means()[0]).abs() < 1e-4);
    assert_eq!(resample(&img, 6), img);
}

#[test]
fn white_balance_puts_every_channel_mean_at_one_half() {
    let data: Vec<f32> = (0..4 * 4 * 3)
        .map(|v| 0.1 + (v % 7) as f32 * 0.05)
        .collect();
    let img = Image2::from_data(4, 4, 3, data).unwrap();
    for m in img.white_balanced().channel_means() {
        assert!((m - 0.5).abs() < 1e-5, "{m}");
    }
}
