//! Training targets: resampling to the training grid and white balance.

use xylem::Image2;

#[test]
fn shrinking_averages_blocks_and_keeps_the_mean() {
    let data: Vec<f32> = (0..36).map(|v| v as f32).collect();
    let img = Image2::from_data(6, 6, 1, data).unwrap();
    let half = img.resampled(3, 3);
    // Top-left 2 x 2 block: 0, 1, 6, 7.
    assert!((half.get(0, 0, 0) - 3.5).abs() < 1e-5);
    assert!((half.get(2, 2, 0) - (28.0 + 29.0 + 34.0 + 35.0) / 4.0).abs() < 1e-5);
    // A non-integer factor (6 -> 4, 1.5 pixels per output pixel): each output pixel is the
    // mean of the pixels its footprint touches (rows and columns 1..3 for output (1, 1)).
    let odd = img.resampled(4, 4);
    assert!((odd.get(0, 0, 0) - 3.5).abs() < 1e-5);
    assert!((odd.get(1, 1, 0) - (7.0 + 8.0 + 13.0 + 14.0) / 4.0).abs() < 1e-5);
    assert_eq!(img.resampled(6, 6), img);
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

/// Enlarging: displays repeat pixels (`resized`), training targets interpolate (`resampled`).
#[test]
fn enlarging_repeats_for_display_and_interpolates_for_training() {
    let data: Vec<f32> = (0..36).map(|v| v as f32).collect();
    let img = Image2::from_data(6, 6, 1, data).unwrap();
    let shown = img.resized(12, 12);
    assert_eq!((shown.get(3, 2, 0), shown.get(3, 3, 0)), (7.0, 7.0));
    let trained = img.resampled(12, 12);
    // Output column 3 has its centre at input column 1.25, row 3 at input row 1.25.
    let expected = 7.0 + 0.25 * 1.0 + 0.25 * 6.0;
    assert!(
        (trained.get(3, 3, 0) - expected).abs() < 1e-5,
        "{}",
        trained.get(3, 3, 0)
    );
    assert!((trained.channel_means()[0] - img.channel_means()[0]).abs() < 1e-4);
}
