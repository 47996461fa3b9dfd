#pragma once
// Photo analysis's rules and their thresholds, one documented set (private to
// analysis/src; pixel figures in working pixels, the photo after any downscale;
// docs/analysis.md, "Where the code is"). One namespace per stage that decides
// with them: segmentation (feathers told from the card, and in separate.cpp and
// rows.cpp touching ones cut apart and faint rows joined and cut), quills (shingled
// rows cut into one feather per quill), shaft (the
// rachis traced, rows and fans of feathers told apart), vane (widths, barb angles
// and spacing, the downy base). Each threshold has one comment line: what it
// separates and where it was measured; "not tuned" or "not documented" where no
// measurement is on record. The stage's sources read its namespace unqualified
// (using namespace thresholds::STAGE).
#include <cstddef>

namespace plumage::analysis::thresholds::segmentation {

// --- background and colour threshold (segment_feathers)
// border luminance below it: a dark card (the spoonbill sheet's black), at or above: a light one; middle of the 8-bit grey range, not tuned
inline constexpr int kDarkBackgroundLuma = 128;
// kernel (px) of the blur on the colour distance before thresholding: grain and JPEG noise below it, barbs and strokes above; docs step 2
inline constexpr int kDistBlurKsize = 5;
// sigma (px) of that blur: a light denoise; not documented as tuned
inline constexpr double kDistBlurSigma = 1.0;
// floor of the colour-distance threshold (8-bit levels): a clean card's grain below, feathers above, where Otsu goes lower; docs step 2
inline constexpr double kMinThreshold = 12.0;
// threshold and hysteresis level at least this many sigma (MAD) of the border luminance: card grain and a scan's striped edge below; docs step 2
inline constexpr double kBorderNoiseSigmas = 4.0;
// opening disc (px) on photos under kOpenGrowPx: grid lines, axis lines and hairline text up to 2 px wide go, feathers stay; docs step 2
inline constexpr int kOpenKsize = 3;
// the opening's disc grows by 2 px per this many px of the photo's short side (big photos draw lines wider); docs step 2 ("larger for big photos")
inline constexpr int kOpenGrowPx = 1500;
// hysteresis level as a share of the threshold: darker quill ends and downy bases joined to a feather above it, card below; docs step 2 ("half")
inline constexpr double kHysteresisShare = 0.5;
// floor of the hysteresis level (8-bit levels), as kMinThreshold is of the threshold; docs/analysis.md step 2
inline constexpr double kMinLowThreshold = 12.0;

// --- low-contrast outlines: textured parts joined to their feather (grow_into_texture)
// box (px) whose mean is taken from the grey for the texture: barbs 2-7 px apart pass, shading and gradients do not; not tuned
inline constexpr int kTextureBlur = 5;
// box (px) over which the texture's RMS is taken; not tuned
inline constexpr int kTextureWindow = 7;
// texture above the border frame's median by this many sigma (MAD) is a feather's, at or under it the card's grain; not tuned
inline constexpr double kTextureSigmas = 6.0;
// ... and at least this many grey levels: a clean card's grain and JPEG ringing under it; not tuned
inline constexpr int kMinTextureLevels = 3;
// opening disc (px) on the textured pixels: the band of gradient along every edge (2-4 px) goes, a textured half-vane stays; not tuned
inline constexpr int kTextureOpen = 7;
// a textured patch joins its feather only when it adds at least this share of the feather's area: a shadowed half-vane (about 0.4) does, slivers along an edge (blue-jay F40's right vane beside its neighbour) do not; not tuned further
inline constexpr double kMinTexturePart = 0.1;

// --- regions kept: specks, rulings, text (segment_feathers, is_strokes)
// area floor in px (pixels inside the outline): specks below; peregrine sheet (424 x 600): its smallest body feathers are 82-143 px
inline constexpr double kMinAreaPx = 60.0;
// area floor as a share of the photo (0.03 %): specks below, feathers above; peregrine sheet: F29, 92 px inside its outline, over it (76 px)
inline constexpr double kMinAreaShare = 3e-4;
// blobs of this many px or more count as marks in a text line (letters falling apart into pieces count), smaller ones are noise; docs step 2
inline constexpr int kMinMarkArea = 12;
// mean thickness (area / long side, px): rulings and axis lines below, vanes above; docs/analysis.md step 2 ("rulings are rejected")
inline constexpr double kMinThickness = 3.0;
// a region under this share of the largest region is text or a label, not a feather; docs/analysis.md step 2 ("under 0.5 % of the largest")
inline constexpr double kMinRelativeArea = 0.005;
// regions shorter than this share of the photo's height may be text (asked whether they stand in a line); taller ones never are; docs step 2
inline constexpr double kTextHeight = 0.06;
// marks in a line (the region included) from which it is a title or word, fewer stand alone; robin handwriting, spoonbill print (docs step 2)
inline constexpr int kTextRun = 3;
// marks in one text line are within this factor of each other's height; docs/analysis.md step 2 ("within a factor 2")
inline constexpr int kLineHeightRatio = 2;
// marks in one text line overlap vertically by at least this share of the smaller height; docs/analysis.md step 2
inline constexpr double kLineOverlap = 0.5;
// the next mark in a line may overlap this one horizontally by up to this many px (touching or kerned letters)
inline constexpr int kMarkOverlapPx = 2;
// gap to the next mark in a line at most this many heights (the taller's): letters of a word within, separate marks beyond; docs step 2
inline constexpr double kMarkGap = 1.5;
// letter test: opening disc diameter as a share of the mark's height (strokes thinner vanish); docs step 2 ("a disc half its height across")
inline constexpr double kStrokeDisc = 0.5;
// share of a mark's pixels surviving that opening: letters 0-20 % below (spoonbill print, robin handwriting), small feathers 89-97 % above
inline constexpr double kStrokeSurvives = 0.5;
// opening disc (px) for marks kept only on their pixel count: print strokes 1-2 px wide vanish; spoonbill sheet's axis label "28" (docs step 2)
inline constexpr int kPrintDisc = 3;

// --- barb gaps (close_barb_gaps)
// closing disc radius as a share of the feather's length (disc 0.9 % across): notches between barb tips close, wide splits stay open; docs step 2
inline constexpr double kBarbGapHalfDisc = 0.0045;

// --- touching feathers (core_markers, separate)
// a blob whose largest distance to the background is under this (px) is too thin to hold two cores: one feather
inline constexpr int kMinCoreDepthPx = 2;
// core level as a share of the blob's largest distance to the background: necks between touching feathers below; docs "Sheets" (shared sheets)
inline constexpr double kCore = 0.6;
// core pieces and grown pieces under this share of the largest are lobes of one vane, not feathers; shared sheets (docs "Sheets": 15 %)
inline constexpr double kMinPiece = 0.15;
// hull solidity: fans and rows on a string below (reported), single feathers above (0.63-0.99 on the shared sheets); docs "Sheets"
inline constexpr double kMinSolidity = 0.6;
// hull solidity every separated piece must reach to be a feather, as whole feathers must; docs/analysis.md "Sheets" (60 %)
inline constexpr double kMinPieceSolidity = 0.6;
// cut length as a share of the narrower piece's width: barely touching below (accepted cuts 0.05-0.41 on the photos), overlapping above
inline constexpr double kMaxCut = 0.5;

// --- faint feathers (join_faint_pieces, split_faint_row)
// percentile of a region's colour distance that kFaintP95 is compared with (its densest part, not a few dark specks); docs "Sheets"
inline constexpr int kFaintPercentile = 95;
// faint below (that percentile over the threshold; blue-jay grey downy feathers 1.11-1.24), other regions above (1.7 and over); blue-jay sheet
inline constexpr double kFaintP95 = 1.4;
// faint regions that must lie in one region above half the threshold for it to take their place; fewer are left as they are; docs "Sheets"
inline constexpr int kMinFaintPieces = 2;
// directions tried across a faint row (3 deg apart): enough that one runs along the row; docs/analysis.md "Sheets" ("60 directions")
inline constexpr int kRowAngles = 60;
// profile smoothing sigma as a share of the square root of the region's area: fluff's grain below, plumes above; blue-jay sheet (2 %)
inline constexpr double kRowSmooth = 0.02;
// floor of that smoothing sigma (px), so small regions' profiles are still smoothed; not documented as tuned
inline constexpr double kRowMinSigmaPx = 1.5;
// the smoothing kernel reaches this many sigma each way (a Gaussian's weight beyond is negligible); convention, not tuned
inline constexpr int kRowKernelSigmas = 3;
// peak prominence as a share of the profile's maximum: plumes above (blue-jay 0.22-0.95 at 0.75x, 1x, 1.5x, turned), ripples below
inline constexpr double kRowProminence = 0.15;
// each piece this many times as long along the cut as wide: plumes 2.07-3.20 above, a plume cut lengthwise 0.73-1.17 below; blue-jay sheet
inline constexpr double kMinPlumeAspect = 1.8;
// a row of white plumes on a grey card (label_with_pale_parts): profile smoothing as kRowSmooth's; at 2 % the white fluff's barbs pick the direction (21 deg off the row on the blue-jay sheet), at 4-6 % the row (3-6 deg), at 8 % two plumes merge
inline constexpr double kWhiteRowSmooth = 0.06;
// a row of white plumes: each piece this many times as long as wide (kWidthShare); their fluff spreads wider than grey plumes (blue-jay 1.66-2.90 at kWhiteRowSmooth and kWhiteRowTilt), a plume cut lengthwise 0.73-1.17
inline constexpr double kMinWhitePlumeAspect = 1.4;
// a row of white plumes: a cut may lean this far (deg) to run along the gap between plumes that lean apart (blue-jay: the first plume leans 10-15 deg off its neighbour)
inline constexpr double kWhiteRowTilt = 24.0;
// leaning cuts turn about the gap between two bases in this share of the row's length from its base end (a white plume's grey base: a fifth to a third of it on the blue-jay sheet)
inline constexpr double kBaseBand = 0.25;
// a white plume's piece is opened by a disc this wide (px), so the thread its row is glued on (2-4 px on the blue-jay sheet) leaves its outline
inline constexpr int kThreadOpenPx = 9;
// between leaning cuts a piece's width is the middle this share of its pixels across (fluff spreads past a neighbour's cut); convention, not tuned
inline constexpr double kWidthShare = 0.9;
// cuts' own pixels this share of the extent off the middle: the base is on that side (blue-jay groups 0.20-0.23, 0.11-0.13); else not said
inline constexpr double kBaseSide = 0.08;

// --- pale parts on a mid-grey card (label_with_pale_parts, label_contours)
// border luminance from which a card is mid-grey: darker cards have nothing lighter than the feather itself; docs "Pale parts" (60-215)
inline constexpr double kPaleCardMin = 60.0;
// border luminance up to which a card is mid-grey: lighter cards leave no room for paler parts; docs/analysis.md "Pale parts"
inline constexpr double kPaleCardMax = 215.0;
// least lift over the local card (grey levels) for a pale pixel: card variation below, white tips/margins (25-55 levels) above; blue-jay sheet
inline constexpr double kPaleLevels = 15.0;
// the pale level is at least this many sigma (MAD) of the card's grain about the local card; docs/analysis.md "Pale parts" (4 sigma)
inline constexpr double kPaleGrainSigmas = 4.0;
// local card's Gaussian sigma as a share of the photo's short side: the card's drift over centimetres, not the feathers; docs "Pale parts" (3 %)
inline constexpr double kCardBlur = 0.03;
// the local card is averaged at 1/this of the resolution and interpolated back (it changes over centimetres); docs "Pale parts" (1/8)
inline constexpr int kCardScale = 8;
// the wide card average's sigma, in times kCardBlur's: reaches card from inside a large white tip; blue-jay tail tips (docs "Pale parts": 4x)
inline constexpr double kCardWide = 4.0;
// weight of the wide card average: takes over where the near card's weight drops below it (inside a large white tip); docs "Pale parts" (0.05)
inline constexpr double kWideWeight = 0.05;
// rounds of finding card and pale parts in turn (a large white tip lifts the card around it enough to hide itself); docs "Pale parts" (three)
inline constexpr int kPaleRounds = 3;
// feathers and pale parts grown by this (px) before taking the card: their soft edges are not card; docs "Pale parts" ("a few pixels")
inline constexpr int kSoftEdge = 4;
// lighter by this share of the level keeps a pixel out of the next round's card (tips' pixels just short of it); docs "Pale parts" ("half")
inline constexpr double kNearPaleShare = 0.5;
// kernel (px) of the blur on the lift over the local card: card grain below, pale parts above; as kDistBlurKsize
inline constexpr int kLighterBlurKsize = 5;
// sigma (px) of that blur, as kDistBlurSigma; not documented as tuned
inline constexpr double kLighterBlurSigma = 1.0;
// the card's grain is sampled every this many px each way (a median over the card, not over each pixel); speed, not tuned
inline constexpr int kGrainStride = 2;
// least card weight near a pixel for it to be pale: where no card is near (weight about 0) nothing is compared; numerical, not tuned
inline constexpr double kMinCardWeight = 1e-4;
// no pale part within this share of the short side of the border: the scanner's light and dark edge strips; blue-jay sheet (docs: 2 %)
inline constexpr double kPaleFrame = 0.02;
// that frame's floor in px, for small photos
inline constexpr int kPaleFrameMinPx = 2;
// contact reach and bridging disc radius (px): a pale part within it of a region lies along it, farther is apart; docs "Pale parts" (8 px)
inline constexpr int kBridge = 8;
// seeds: colour regions of at least this share of the smallest feather (a white downy feather's grey base is that small); docs "Pale parts"
inline constexpr double kBaseArea = 0.2;
// the most-contact region owns a pale part when at least this share of its area (a white tip on a vane), not (a downy plume on its base)
inline constexpr double kOwnerArea = 0.25;
// owned part: feather-sized regions with this share of the most contact share it (two touching tips); less take none (a small feather beside)
inline constexpr double kMinContact = 0.5;
// unowned part (downy plumes on grey bases): seeds with at least this share of the most contact share it; docs "Pale parts" (5 %)
inline constexpr double kMinBaseContact = 0.05;
// an unowned pale part this many smallest feathers in size, whose core falls into pieces, is cut between them (white plumes that touch); docs "Pale parts"
inline constexpr double kCutPartAreas = 2.0;
// a pale part alone is a feather when this many times the level lighter somewhere: white down 90-100 levels above, blue-jay card by fluff 25 (level 15)
inline constexpr double kAloneLevels = 2.0;

// --- spotted feather on a mid-grey card (segment_feathers)
// whole region's hull solidity from which it may be one spotted feather: peregrine F30 above, touching/overlapping regions (0.70-0.74) below
inline constexpr double kSpottedSolidity = 0.85;
// coloured share of the region under which it may be one spotted feather: peregrine F30 below, touching/overlapping regions (0.77-0.85) above
inline constexpr double kSpottedColour = 0.7;
}  // namespace plumage::analysis::thresholds::segmentation

namespace plumage::analysis::thresholds::shaft {

// --- several feathers in one region (Shaft::several_feathers)
// tips along the more lobed side: under it one feather (1-3 on the photos), at or over it a row on a string; robin F27 6, F13 7, F24 9
inline constexpr int kMinRowTips = 6;
// length / widest row: under it no long axis (lines not read, may be traced across); docs/analysis.md step 4 and "A row whose tips merge"
inline constexpr double kMinAcrossAspect = 1.3;
// blur for the second look at a row's lines, of the widest row: resolved barbs blur away (drawn barbs 0.86), a row's plumes stay (robin rows)
inline constexpr double kAlongBlur = 0.02;
// lines' share along the axis: under it a row of plumes across a string (robin rows 0.09-0.27 at 1 px), over it one feather (0.43-0.94)
inline constexpr double kMaxLinesAlong = 0.33;
// rim lines' share along the axis at kAlongBlur: under it a row (robin rows 0.22-0.54), over it one feather (0.57+; drawn bars 0.79-0.86)
inline constexpr double kMaxRimAlong = 0.6;

// --- the rachis seen and inferred (fit_rachis; docs/analysis.md "The rachis: seen, inferred, and no S the photo does not show")
// path's ridge / feather's mean ridge: at or over it a row is a candidate for the seen rachis, under it not; docs "The rachis" (blue-jay F13)
inline constexpr double kSeenRidge = 3.0;
// gate, px: a candidate within kGateMin + kGateGrowth x rows from the nearest seen row of the curve is seen, beyond it is a line beside the rachis
inline constexpr double kGateMin = 2.0;
// gate growth, px per row from the nearest seen row (see kGateMin); docs/analysis.md "The rachis"
inline constexpr double kGateGrowth = 0.02;
// first run of candidates from the calamus end: gaps of at most this many rows keep one run, longer ones end it; docs/analysis.md "The rachis"
inline constexpr int kRunGap = 2;
// first run from the calamus end: at least this many rows (and 1/kMinRunShareDiv of the rows) is seen, shorter runs lose to the longest
inline constexpr int kMinRunRows = 5;
// first run from the calamus end: at least rows / this (a tenth of the rows; with kMinRunRows); docs/analysis.md "The rachis"
inline constexpr int kMinRunShareDiv = 10;
// rows per B-spline segment of the rachis curve (K = rows / this); docs/analysis.md "The rachis"
inline constexpr int kRowsPerSegment = 6;
// fewest B-spline segments of the rachis curve (K clamped to kMinSegments..kMaxSegments); docs/analysis.md "The rachis"
inline constexpr int kMinSegments = 4;
// most B-spline segments of the rachis curve; docs/analysis.md "The rachis"
inline constexpr int kMaxSegments = 24;
// third-difference penalty weight x n K^5 / (2 pi)^6: passes half of an S one period long over the shaft, a 65th of one half as long
inline constexpr double kStiffness = 1.0;
// row width / widest: at or under it (quill, pointed tip) the mask's middle joins the fit, over it not (AnalysisAsymmetric: bowed 7.3 px)
inline constexpr double kNarrow = 0.3;
// px: a row where the curve comes within this of the mask's edge is held there, farther in it is free; docs/analysis.md "The rachis"
inline constexpr double kInside = 1.5;
// the inside margin is at most this share of the row's width (kInside on wide rows, less on a narrow quill); geometry
inline constexpr double kInsideOfWidth = 0.25;
// weight of a seen row's path point in the rachis fit (the unit; the mask's middle weighs 12 / width^2); docs/analysis.md "The rachis"
inline constexpr double kSeenWeight = 1.0;
// weight of a row held inside the mask in the rachis fit (as a seen row); docs/analysis.md "The rachis"
inline constexpr double kHeldWeight = 1.0;
// most rounds of fit, gate and hold: the rachis fit stops growing well before (guard, not tuned)
inline constexpr int kMaxFitRounds = 40;

// --- which end is the calamus (calamus_end; docs/analysis.md step 4)
// row width / widest: under it a row at an end is narrow (bare quill or narrowing tip), the run the calamus rule compares; docs step 4
inline constexpr double kRunWidth = 0.3;
// row width / widest: under it a row at an end is quill-thin; a half disc has a tenth as many such rows as under kRunWidth, a taper a third
inline constexpr double kQuillWidth = 0.1;
// rows under kQuillWidth at an end: at least this many (and 1/kQuillRunDiv of its kRunWidth run) is a quill, fewer a tip; docs step 4
inline constexpr int kMinQuillRows = 3;
// an end is a quill when kQuillRunDiv x its rows under kQuillWidth reach its rows under kRunWidth (half; half disc a tenth, taper a third)
inline constexpr int kQuillRunDiv = 2;
// both runs at most this share of the rows and no quill: the run rule is a guess, the shape cues may overrule it; blue-jay F12, F22
inline constexpr double kFewRunRows = 0.06;
// the ridge cue reads the end rows / this (a fifth) at each end; docs/analysis.md step 4
inline constexpr int kEndRowsDiv = 5;
// the ridge cue reads at least this many rows at each end; geometry (a short feather)
inline constexpr int kMinEndRows = 2;
// end's ridge / other end's: at or over it the rachis is stronger toward that end (calamus cue); 1.5 leaves blue-jay F19, 1.15 turns robin F43
inline constexpr double kRidgeEndRatio = 1.3;

// --- two quills at the calamus end (quills_at_calamus; docs/analysis.md "Sheets", "Feathers side by side")
// rows read from the calamus end until the mask is this share of its widest (the quills' part, before the vanes)
inline constexpr double kQuillZoneWidth = 0.5;
// px between mask pieces in a row: at or over it the row holds two quills, under it one (pairs' gaps 24-60 px); docs "Feathers side by side"
inline constexpr int kMinGap = 4;
// rows of two quills in a run: at least this many (and kMinStretch of the rows) are two feathers; a glue band (blue-jay F44) gives 7
inline constexpr int kMinRows = 8;
// run of two-quill rows / the feather's rows: at or over it two feathers (robin F16 9 of 87), under it a split or tuft
inline constexpr double kMinStretch = 0.1;
// median gap / widest row: at or over it two quills (pairs 0.32-0.49), under it one (robin F14: 5 of 44 px)
inline constexpr double kMinGapOfWidest = 0.2;

// --- a row of feathers on a string: tips along a side (tips_along_a_side; docs/analysis.md "A row of feathers on a string")
// extent profile averaged over 2 max(kTipSmoothMin, rows / kTipSmoothDiv) + 1 rows: fewest rows each side (ripples of a flat top are one tip)
inline constexpr int kTipSmoothMin = 3;
// extent profile smoothing: rows / this each side (see kTipSmoothMin)
inline constexpr int kTipSmoothDiv = 60;
// prominence / largest extent: at or over it a tip stands out (a row's feathers), under it a notch or ripple; other regions 1-3 tips
inline constexpr double kTipProminence = 0.25;

// --- coarse lines (coarse_lines; docs/analysis.md "A fan of overlapping feathers")
// px, Gaussian blur before the gradients of the fine lines (fans, turning, a row's first look); docs "Sheets" ("at 1 px")
inline constexpr double kLineBlur = 1.0;
// structure tensor integrated over this share of the widest row: barbs blur away, edges, rachis and colour bands stay; goldfinch F3
inline constexpr double kIntegration = 0.05;
// px, the least integration scale (a narrow region's lines); untuned floor
inline constexpr double kMinIntegration = 1.5;
// px, erosion kernel side: lines are read at mask pixels 2 px in from the outline, not on its own edge; docs "A fan of overlapping feathers"
inline constexpr int kInnerKernel = 5;

// --- a fan of overlapping feathers (fan_spread_deg; docs/analysis.md "A fan of overlapping feathers")
// lines: fewer than this and no fan is looked for (too few to place a point); untuned guard
inline constexpr int kMinFanLines = 50;
// weighted mean cos^2 of line to bearing: at or over it the lines point at one point (goldfinch F3 0.954-0.966), under it not (0.894 or less)
inline constexpr double kMinAlignment = 0.92;
// deg, bearings' 10-90 % range: from it up to kMaxSpread a fan (goldfinch F3 114, drawn fans 91-127), under it no fan
inline constexpr double kMinSpread = 30;
// deg, bearings' range: over it the point lies inside one feather (its lines seen all round), no fan
inline constexpr double kMaxSpread = 180;
// lower weighted quantile of the bearings for the spread (10 %: stray lines left out); docs "A fan of overlapping feathers"
inline constexpr double kSpreadLowQuantile = 0.1;
// upper weighted quantile of the bearings for the spread (90 %); docs "A fan of overlapping feathers"
inline constexpr double kSpreadHighQuantile = 0.9;

// --- a round region traced across its principal axis (doubled_angle_mean, trace_along; docs/analysis.md step 4)
// length of lines' doubled-angle mean: at or over it a round region turns (a blue-jay white plume read with half its neighbour 0.51, goldfinch F17 0.60), under it not (drawn 0.17-0.19)
inline constexpr double kMinLineStrength = 0.15;

// --- a row whose tips merge (lines_along_axis; docs/analysis.md "A row whose tips merge")
// rim: mask pixels within this share of the widest row of the outline (a row's ragged tips and string); docs "A row whose tips merge"
inline constexpr double kRim = 0.1;

// --- the chevron score (chevron_score)
// px, Gaussian over which the structure tensor's cross term and energy are integrated: the barbs' slant, not single barbs; untuned
inline constexpr double kChevronIntegration = 2.0;

// --- the best path (best_path, trace_along; docs/analysis.md step 4)
// columns the path may move from one row to the next (<= 2 px sideways per row: a rachis leans, it does not jump)
inline constexpr int kMaxStep = 2;
// price per column moved / mean ridge r (r/2): a smooth path, yet a rachis that leans is followed; docs step 4
inline constexpr double kMovePrice = 0.5;
// chevron weight / move price (4 x r/2 = 2r): where lines compete it decides; at 4r it outweighed a barred rachis (blue-jay tail feather 3)
inline constexpr double kChevronWeight = 4.0;

// --- the path kept from straying (robust_smooth, trace_along; docs/analysis.md step 4, robin F14)
// rounds of local linear fits weighted by Tukey's biweight (a stretch away from the rest stops pulling); docs step 4
inline constexpr int kSmoothRounds = 3;
// Tukey's biweight tuning constant, times the residuals' MAD scale: residuals beyond it weigh nothing (the standard value)
inline constexpr double kBiweight = 4.685;
// robust smooth half window: at least this many rows each side; untuned floor
inline constexpr int kSmoothHalfMin = 10;
// robust smooth half window: rows / this (a quarter) each side, so a stretch shorter than that does not pull; robin F14 (a ninth)
inline constexpr int kSmoothHalfDiv = 4;
// px, the least corridor: a path farther than the corridor from its smooth strays and is traced again within it
inline constexpr double kCorridorMin = 3.0;
// corridor / median row width: farther a stray (robin F14 13-21 px), nearer the rachis; ShaftStaysOnTheRachisBesideAStrongerLine
inline constexpr double kCorridor = 0.1;
// px, the least band about the rachis curve in which the path is traced again; docs/analysis.md "The rachis"
inline constexpr double kRetraceMin = 2.0;
// band about the rachis curve / median row width in which the path is traced again (5 %); docs/analysis.md "The rachis"
inline constexpr double kRetrace = 0.05;

// --- a rounded tip where the rachis fades (straighten_faded_tip; docs/analysis.md step 4)
// rows: a path shorter than this is left as traced (too short to tell a faded tip); untuned
inline constexpr int kMinFadeRows = 40;
// ridge along the path averaged over max(kFadeSmoothMin, rows / kFadeSmoothDiv) rows each side: at least this many; untuned
inline constexpr int kFadeSmoothMin = 2;
// ridge smoothing along the path: rows / this each side (see kFadeSmoothMin)
inline constexpr int kFadeSmoothDiv = 100;
// typical ridge: the median with rows / this (a fifth) left out at each end, where quill and tip differ; untuned
inline constexpr int kTypicalTrimDiv = 5;
// the ridge has faded where it is under typical / this (a third); docs step 4
inline constexpr int kFadedRidgeDiv = 3;
// rows the straight line is fitted over before the faded part: at least this many; untuned
inline constexpr int kFadeFitMin = 10;
// rows the straight line is fitted over: rows / this (see kFadeFitMin)
inline constexpr int kFadeFitDiv = 20;
// faded rows at the tip: fewer than this, nothing to mend, more (up to rows / kMaxFadedDiv) straightened; untuned
inline constexpr int kMinFadedRows = 3;
// faded rows at the tip: more than rows / this (a quarter), no rachis to trust, left as traced; untuned
inline constexpr int kMaxFadedDiv = 4;
// rows the straight line leaves the mask early: over max(this, rows / kMaxBeyondDiv) a hooked tip (kept as traced), else a rounded one; untuned
inline constexpr int kMaxBeyondRows = 3;
// rows the straight line may leave the mask early: rows / this (see kMaxBeyondRows)
inline constexpr int kMaxBeyondDiv = 100;

// --- the straightened frame and the ridge (trace_along; docs/analysis.md step 4)
// px of room around the mask in the straightened frame (blurs and ridge offsets read no edge); geometry
inline constexpr int kFrameMargin = 4;
// rows the mask spans (last - first): under this a region is too short to trace a shaft (an error), at or over it traced; guard
inline constexpr int kMinShaftRows = 8;
// px, the least sigma of the blur along the axis (slanted barbs blur away, the rachis stays); untuned floor
inline constexpr double kAlongSmoothMin = 2.0;
// sigma of the blur along the axis / rows of the frame (1 %); docs step 4
inline constexpr double kAlongSmooth = 0.01;
// px, the smallest offset either side at which the ridge (line detector) compares a pixel with the vane; docs step 4 ("several widths")
inline constexpr int kRidgeMinOffset = 2;
// px, the largest ridge offset is at least this; untuned floor
inline constexpr int kRidgeMaxOffsetMin = 3;
// the largest ridge offset / rows of the frame (2 %): a rachis at most about that wide scores; untuned
inline constexpr double kRidgeMaxOffset = 0.02;
// ridge offsets step by one px below this, then by kRidgeGrowth; untuned
inline constexpr int kRidgeStepFrom = 4;
// ridge offsets grow by this factor from kRidgeStepFrom on (a few widths, few passes); untuned
inline constexpr double kRidgeGrowth = 1.5;

// --- the shaft's output (trace_along, spline_length)
// path points: about this many samples from calamus to tip (every (rows / this)-th row); resolution, untuned
inline constexpr int kPathSamples = 200;
// rows of bare quill at the calamus: at least this many and the shaft's width is their median width, fewer and it is a share of the length
inline constexpr int kMinQuillWidthRows = 3;
// px, the least shaft width when no quill is measured; untuned floor
inline constexpr double kMinShaftWidth = 2.0;
// shaft width / length when no quill is measured (a typical rachis proportion); not measured on the photos
inline constexpr double kShaftWidthOfLength = 0.008;
// ridge on the path / mean ridge: at or under it the shaft's confidence is 0 (a path no stronger than the typical line); untuned
inline constexpr double kZeroConfidenceContrast = 1.0;
// ridge contrast above kZeroConfidenceContrast at which the shaft's confidence reaches 1; untuned
inline constexpr double kFullConfidenceSpan = 3.0;
// chords of the polyline that measures a spline's length (numerics, not tuned)
inline constexpr int kLengthSamples = 512;

// a white plume cut from its row (Component::quill_px): within this share of its length from the calamus the traced shaft keeps to
// a corridor about the calamus-to-tip line (kQuillCorridor of the length each side): without it blue-jay F19, F26 were read from the foot of the cuts beside them, 3-6 mm off, with it 1-2 mm (0.05-0.12 alike)
inline constexpr double kQuillReach = 0.15;
inline constexpr double kQuillCorridor = 0.1;

}  // namespace plumage::analysis::thresholds::shaft

namespace plumage::analysis::thresholds::vane {

// --- unrolling along the shaft and stations (unroll, measure_vanes)
// samples of the shaft curve in its arc-length table (lengths between them interpolated); numerics, not tuned
inline constexpr int kUnrollArcSamples = 2048;
// segments of the shaft polyline the outline's reach is measured to; numerics, not tuned
inline constexpr int kReachAxisSegments = 128;
// the reach is read at every this-th outline point (speed); not tuned
inline constexpr int kReachContourStride = 2;
// columns (px) unrolled past the outline's farthest reach from the shaft, so the outermost mask pixel lies inside; not tuned
inline constexpr int kUnrollMarginPx = 4;
// cap on the unrolled half-width (px), bounding memory for a degenerate outline; none of the six shared photos reaches it; not tuned
inline constexpr int kUnrollMaxHalfWidthPx = 4096;
// least half-height (rows) of a station's window when there are more stations than rows allow (windows >= 5 rows); not documented
inline constexpr int kStationMinHalfRows = 2;
// barb angle (deg) given at zero confidence to a side with no reading at any station (a placeholder: not trusted); not tuned
inline constexpr double kAngleFillDeg = 45.0;

// --- barb angle (angle_mode; docs/analysis.md "How it works", step 5)
// sigma of the blur subtracted before the structure tensor (and the downy texture): finer is barbs, broader is shading, highlights, bars; docs step 5
inline constexpr double kBarbScalePx = 4.0;
// sigma each pixel's tensor is integrated over: wide enough for the local barb orientation, narrow enough to keep it local; docs step 5
inline constexpr double kTensorScalePx = 1.5;
// sigma (G2) of the gradient averaging for the step-edge share: a grating of barbs cancels over it, a step edge does not; docs step 5
inline constexpr double kEdgeScalePx = 2.0;
// step-edge share at which a pixel stops voting (~0.5 on a blurred step, < 0.05 on barbs 3-10 px apart); AnalysisBarring.SlantedBarsDoNotSetTheBarbAngle
inline constexpr double kEdgeShare = 0.25;
// side (px) of the square the step-edge share is dilated over: the tensor carries an edge's orientation a few px either side of it; docs step 5
inline constexpr int kEdgeDilatePx = 5;
// diameter (px) of the ellipse the mask is eroded by: angles and texture are read >= 3 px inside, off the outline; docs step 5, closed-loop study
inline constexpr int kInteriorErodePx = 7;
// inner edge of the barb-angle and texture window, as a fraction of the vane's width (or the shaft's width if wider); docs step 5 ("15-85 %")
inline constexpr double kAngleInner = 0.15;
// outer edge of that window as a fraction of the width (the outline's edge beyond); docs step 5, the closed-loop truth reads the same part
inline constexpr double kAngleOuter = 0.85;
// half-width in 1-degree bins of the histogram smoothing before the mode is taken: noise vs. two nearby modes; docs step 5 ("+-3 deg")
inline constexpr int kAngleHistSmoothDeg = 3;
// votes within this of the mode (deg) refine the angle, farther ones (bars' edges at ~90 deg, highlights) do not; docs step 5
inline constexpr double kAngleRefineDeg = 8.0;
// votes within this of the mode (deg) count toward the angle's confidence (share and mean coherence); docs step 5
inline constexpr double kAngleConfWindowDeg = 10.0;
// scale of share x mean coherence so a clean barb pattern reads confidence ~1; docs step 5
inline constexpr double kAngleConfScale = 1.4;
// barb angle (deg) under which a reading keeps its confidence; at or over it it points back toward the calamus, which no barb does; geometry
inline constexpr double kAngleMaxDeg = 90.0;

// --- barb spacing (spacing; docs/analysis.md "How it works", step 5)
// spacing windows shorter than this (rows) read nothing (too few barbs); windows hold >= min(L, kSpacingMinHalfRows + 1) rows: tiny shafts only; not documented
inline constexpr int kSpacingMinRows = 24;
// shortest period searched (px): below it the periodogram cannot see barbs; docs step 5 and "Barb density" (period >= 2.5 photo px)
inline constexpr double kSpacingMinPeriodPx = 2.5;
// the longest period searched is at least this times the shortest (a band of at least an octave, for short windows); not documented
inline constexpr int kSpacingMinBandRatio = 2;
// the longest period searched is the window's length over this (a quarter: at least four periods per window); docs step 5
inline constexpr double kSpacingWindowPeriods = 4.0;
// least half-width (samples) of the running mean removed as shading; otherwise half the longest period searched; not documented
inline constexpr int kSpacingHighPassMinHalf = 3;
// least half-length (rows) of a station's spacing window, for several periods; the closed-loop truth reads roots within +-48 px (docs "Closed-loop accuracy")
inline constexpr int kSpacingMinHalfRows = 48;
// frequencies sampled evenly in 1/period from the longest to the shortest period searched; a multiple of the Goertzel block (8); not tuned
inline constexpr int kSpacingFrequencies = 240;
// spacing lines stop at this fraction of the width: farther out barbs at slightly different angles meet in pairs (was 0.60); closed-loop study, feather 12
inline constexpr double kSpacingOuter = 0.45;
// spacing lines start at this fraction of the width (or at the shaft's width if wider): inside it the rachis; docs step 5 ("15-45 %")
inline constexpr double kSpacingInner = 0.15;
// the spacing band is stepped in this many parts, i.e. read on up to 13 lines (a step of at least 1 px); docs step 5
inline constexpr int kSpacingLineSteps = 12;
// share of a line's rows inside the mask for it to be read; fewer: it leaves the vane (a split, the edge) and is skipped; not documented
inline constexpr double kSpacingLineInside = 0.9;
// octave check: bins either side of twice the peak's frequency searched for its harmonic (bin jitter of the peak); not documented
inline constexpr int kOctaveSearchBins = 4;
// octave check: harmonic power / peak power at or over which a local-peak harmonic is the spacing (barbs alternating in brightness); docs step 5
inline constexpr double kOctavePeakShare = 0.25;
// spacing confidence is 0 up to this peak / band-mean ratio: noise peaks reach a few times the mean; comment in spacing()
inline constexpr double kSpacingConfFloor = 5.0;
// ratio above kSpacingConfFloor at which spacing confidence reaches 1 (a single clean period, >= 20x the mean); not documented
inline constexpr double kSpacingConfRange = 15.0;

// --- fanning correction of the spacing (correct_spacing_for_fanning; docs step 5, "Closed-loop accuracy")
// stations either side of a station in the line whose slope of cot(theta) corrects its spacing (seven in all); docs step 5
inline constexpr int kFanningNeighbours = 3;
// barb-angle confidence over which a station's angle enters that line; at or under it the angle is not trusted for the slope; not documented
inline constexpr double kFanningMinConf = 0.3;
// barb angle (radians, ~2.9 deg) over which a station's cot(theta) enters the line; flatter ones blow cot up; not documented
inline constexpr double kFanningMinAngleRad = 0.05;
// the fanning factor 1 + o d(cot theta)/ds is clamped to [min, max] before dividing the period; closed-loop study (falling angle profiles)
inline constexpr double kFanningFactorMin = 0.7;
// upper clamp of that factor; closed-loop study (falling angle profiles: 5.4-6.5 % spacing error to 2-3 %)
inline constexpr double kFanningFactorMax = 1.4;

// --- downy base (find_downy_base; docs/analysis.md "Downy base")
// a station's texture is read when its window holds >= this x P^2 pixels (a patch two barb periods square); fewer: not read; docs "Downy base"
inline constexpr int kDownyMinPeriodsSq = 4;
// the vane's texture is the median over stations at t >= this (where a feather is pennaceous, past any down); docs "Downy base"
inline constexpr double kDownyVaneFromT = 0.4;
// ... and t <= this (short of the tip); docs "Downy base"
inline constexpr double kDownyVaneToT = 0.8;
// station texture / vane texture: under it down, over it vane; pink photo (base 0.09-0.47, vane 0.75 up), tests/analysis_vane_test.cpp
inline constexpr double kDownyTexture = 0.5;
// fewest stations in a downy run: one alone can be a window caught on the vane's ragged base; docs "Downy base"
inline constexpr std::size_t kDownyMinStations = 2;
// a downy run whose last station is at t >= this is half the feather, not a base, and is dropped; docs "Downy base"
inline constexpr double kDownyMaxEndT = 0.5;

// --- open vanes, plumes (vane_open_share; docs/analysis.md "Plumes: an open vane")
// a pixel is the card's when no channel differs from the card's colour by more than this x the card's grain (MAD sigma); docs "Plumes"
inline constexpr double kOpenCardSigmas = 3.0;
// ... or than this many grey levels, on a card without grain; docs "Plumes"
inline constexpr double kOpenMinLevels = 4.0;
// the vane is read from this share of the side's width out (past the shaft and its shading) ...; docs "Plumes"
inline constexpr double kOpenFromWidth = 0.15;
// ... to this share (short of the ragged edge, where every vane lets the card through); docs "Plumes"
inline constexpr double kOpenToWidth = 0.85;
// a feather is a plume when both sides' open share is at least this: shared photos' plumes (blue-jay F15, F19, F23, F26) 0.67-0.84, every other feather's lesser side <= 0.22; drawn plumes 0.43-0.48 (blur narrows the gaps); docs "Plumes"
inline constexpr double kPlumeOpenShare = 0.4;

}  // namespace plumage::analysis::thresholds::vane

namespace plumage::analysis::thresholds::quills {

// --- quills found as stems that leave the vane (quills.cpp, find_quills)
// opening disc radius as a share of the region's largest inscribed radius: quills (2-8 % of a vane's width across) vanish, vanes stay; synthetic shingled rows, not tuned on photos
inline constexpr double kOpenRadius = 0.25;
// the opening disc's radius is at least this many px (a quill 1-2 px wide at the sheets' smallest feathers is under it)
inline constexpr int kMinOpenRadiusPx = 2;
// a stem is at least this long, as a share of the opening disc's diameter (half the vane's widest half-width): a calamus over it, barb tips and notches under it; not tuned
inline constexpr double kMinLength = 1.0;
// a stem is at least this share of the region's extent along it: a calamus (0.12-0.3 of its feather: blue-jay F35, synthetic rows) over it, a curl of down at a plume's edge (blue-jay F36, 0.08) under it
inline constexpr double kMinShareOfExtent = 0.1;
// a stem's mean width (area / length, over its outer two thirds) at most this share of the opening disc's diameter: a quill under it, a lobe of vane or a downy tuft over it; not tuned
inline constexpr double kMaxWidth = 0.5;
// width over the stem's outer third over its middle third, at least: a quill keeps its width, a pointed tip narrows to nothing (about 1/3); not tuned
inline constexpr double kMinEndWidthRatio = 0.5;
// pixels off the stem's axis at most this many of its mean widths (plus 1.5 px): a straight quill within, a curl of down or a split barb beyond; not tuned
inline constexpr double kMaxBend = 1.5;
// a stem's line is followed into the vane from this many disc radii past its base ...; not tuned
inline constexpr double kIntoFrom = 2.0;
// ... to this many (5 points in all); not tuned
inline constexpr double kIntoTo = 4.0;
// ... where it lies at least this many radii from the card (median): a quill's rachis runs into the vane's middle, a split-off strip of barbs or down along its edge (blue-jay F15, F19, F36) does not
inline constexpr double kMinInto = 1.0;
// quills of one row point within this many degrees of their mean direction: a shingled row within, a fan or feathers laid every way beyond; synthetic rows tilt +-6 deg
inline constexpr double kMaxRowSpread = 25.0;
// a piece of a split row keeps at least this share of the row's median piece area: smaller means the row was not followed; not tuned
inline constexpr double kMinPieceShare = 0.35;
// ... and at most this share of it: an end strip that large holds a neighbour whose quill was not seen; not tuned
inline constexpr double kMaxPieceShare = 1.8;
// a strip whose parts apart from the one holding its quill come to more than this share of that one is cut in two: the row is not followed; not tuned
inline constexpr double kMaxCutOffShare = 0.25;
// consecutive quills at most this many median gaps apart along the row: a wider gap is a quill not seen; synthetic rows are within 1.2
inline constexpr double kMaxGapRatio = 1.6;

}  // namespace plumage::analysis::thresholds::quills
