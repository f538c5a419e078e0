//! The documentation stays true: every `tensorglyph` command line of the README and the book
//! runs (readme.rs), and every link and anchor of both holds (book.rs). tests/README.md is the
//! map.

#[path = "../common/xvfb.rs"]
mod xvfb;

mod book;
mod readme;
