//! Everything a command writes: number formatting, the terminal report,
//! CSV and JSON, atomic files, the history recorder and the progress bar.

pub mod boundary;
pub mod covering_picture;
pub mod files;
pub mod format;
pub mod history;
pub mod html;
pub mod interrupt;
pub mod observer;
pub mod progress;
pub mod publish;
pub mod report;
pub mod restitution;
pub mod run_plots;
pub mod table;
pub mod validation;
