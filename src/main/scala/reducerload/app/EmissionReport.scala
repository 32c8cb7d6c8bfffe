package reducerload.app

/** What `emit` writes about a module: the .sv header's lines, report.md and report.json. */
trait EmissionReport {
  def moduleName: String
  def latency: Int
  def throughput: String
  def portLines: Seq[String]
  def summaryLines: Seq[String]
  def markdown: String
  def json: String
}
